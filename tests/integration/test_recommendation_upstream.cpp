// Upstream advice end to end over DDS, on simulated data where the answer is known: bearing 2 drives bearing 1
// (instantaneously and with one lag); bearings 3 and 4 are independent. From snapshot 250 bearing 2's OWN
// level rises; bearing 1 follows only through the causal link. The three services (shipped alarm parameters)
// must alarm on bearing 1 and recommend acting on bearing 2, with a predicted reduction of bearing 1.
// Two estimator set-ups:
//  * Configured: told the instantaneous graph "bearing2 -> bearing1", raw (un-centred) inputs.
//  * Learned: told nothing; it centres the inputs and learns the causal order with VAR-LiNGAM on the first
//    200 snapshots (the noise is uniform, so the order is identifiable), then must publish x12 but not x21,
//    and the what-if on bearing 2 must predict no change of the unlinked bearings 3 and 4.
#include "condition_level_params.hpp"
#include "dds_observer.hpp"
#include "process_expect.hpp"
#include "process_runner.hpp"
#include "simulated_shaft_table.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace causal::test;

namespace {

constexpr int kChangeAt = causal::test::kSimulatedShaftChangeAt;

struct Scenario {
  const char* name;
  const char* graph;      // condition_level.instantaneous_graph
  const char* structure;  // condition_level.structure (flow style)
};

causal_twin::WhatIfRequest sustained_cut(int channel) {
  causal_twin::WhatIfRequest q;
  q.request_id("it-" + std::to_string(getpid()));
  q.asset_group("sim-shaft");
  q.intervene_channel(static_cast<std::uint16_t>(channel));
  q.delta(std::log(0.9));  // a sustained 10 % cut of the channel's level
  q.sustained(true);
  return q;
}

void PrintTo(const Scenario& sc, std::ostream* os) { *os << sc.name; }

const Scenario kScenarios[] = {
    {"Configured", "bearing2 -> bearing1",
     "{calibration_samples: 0, centre: false, causal_order: configured, prune_threshold: 0.0}"},
    {"Learned", "", "{calibration_samples: 200, centre: true, causal_order: lingam, prune_threshold: 0.0}"},
};

}  // namespace

class RecommendationUpstream : public ::testing::TestWithParam<Scenario> {};

TEST_P(RecommendationUpstream, AlarmOnFollowerRecommendsActingOnTheUpstreamChannel) {
  const Scenario& sc = GetParam();
  const bool learned = std::string(sc.graph).empty();
  const fs::path work = fs::temp_directory_path() / ("causal_it_rec_" + std::string(sc.name) + "_" + std::to_string(getpid()));
  fs::create_directories(work);
  const std::string table = causal::test::write_simulated_shaft_table(work, 20261122);
  const std::string d = std::to_string(causal::test::private_domain_id(learned ? 4 : 3));
  DdsObserver observer(std::stoi(d));
  ServiceProcess alarm("alarm-recommender", {ALARM_RECOMMENDER_BIN, "--domain", d, "--idle-exit", "20", "--max-runtime", "300"},
                       (work / "alarm.log").string());
  ServiceProcess estimator("causal-estimator",
                           {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--params",
                            write_condition_level_params(work / "estimator.yaml", sc.graph, sc.structure),
                            "--idle-exit", "3", "--max-runtime", "300", "--wait-for", "alarm-recommender", "--wait-for", "test-observer"},
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        {SENSOR_REPLAY_BIN, "--domain", d, "--features", table, "--feature-name", "meanabs",
                         "--asset-group", "sim-shaft", "--wait-for", "causal-estimator", "--wait-timeout", "60"},
                        (work / "replay.log").string());
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(replay, std::chrono::seconds(240)));

  // The estimator drains its output after the replay has gone: ask once it has published everything and left
  // (the recommender then holds the final model, so both askers below get the same answer).
  ASSERT_TRUE(estimator.wait(std::chrono::seconds(120)).has_value()) << estimator.output();
  // On-demand what-if over DDS while the recommender still runs: a sustained 10 % cut of bearing 2's level.
  const auto reply = observer.ask(sustained_cut(2), std::chrono::seconds(20));
  ASSERT_TRUE(reply.has_value()) << "no what-if reply; alarm log:\n" << alarm.output();
  ASSERT_TRUE(reply->ok()) << reply->error();
  ASSERT_EQ(reply->effect_median().size(), 4u);
  std::printf("[%s] what-if: %s\n", sc.name, reply->text().c_str());
  for (std::size_t k = 0; k < 4; ++k) {
    std::printf("[%s]   bearing%zu: %s %+.4f, 90 %% interval [%+.4f, %+.4f] log-level\n", sc.name, k + 1,
                reply->answer_kind().c_str(), reply->effect_median()[k], reply->effect_low()[k], reply->effect_high()[k]);
  }
  // The answered effect: a steady state, or (the estimated model absorbs bearing 2's ramp in its self lag and
  // ends near or past a unit root) the effect after 12 snapshots. In the TRUE system both are the same to
  // 0.3^12 = 5e-7 of the effect, so one truth serves both.
  ASSERT_TRUE(reply->answer_kind() == "steady_state" || reply->answer_kind() == "horizon") << reply->error();
  // Bearing 1 follows bearing 2 (true steady-state elasticity (0.8 + 0.2) / (1 - 0.3) = 1.43): it must fall.
  EXPECT_LT(reply->effect_median()[0], 0.0) << reply->text();
  EXPECT_NEAR(reply->effect_median()[1], std::log(0.9), 1e-12) << "the intervened channel moves by delta";
  if (learned) {
    // Bearings 3 and 4 have no path from bearing 2: the true effect is 0 and must lie in the stated interval,
    // and the point prediction must be small next to bearing 1's (true elasticity 1.43: -0.151 in log units).
    // (Un-centred inputs, as in the Configured set-up, give -15 % here: see the printed what-if.)
    // Bearing 1's true steady-state effect lies in the stated interval (un-centred, it does not).
    const double truth = (0.8 + 0.2) / (1.0 - 0.3) * std::log(0.9);
    EXPECT_LE(reply->effect_low()[0], truth) << reply->text();
    EXPECT_GE(reply->effect_high()[0], truth) << reply->text();
    for (int k : {2, 3}) {
      EXPECT_LE(reply->effect_low()[k], 0.0) << reply->text();
      EXPECT_GE(reply->effect_high()[k], 0.0) << reply->text();
      EXPECT_LT(std::abs(reply->effect_median()[k]), 0.2 * std::abs(reply->effect_median()[0]))
          << reply->text();
    }
  }
  // The same question from the operator's command line (causal-ask), and one the twin must refuse.
  if (!learned) {
    ServiceProcess ask("causal-ask", {CAUSAL_ASK_BIN, "--domain", d, "--asset-group", "sim-shaft", "--intervene", "2",
                                      "--percent", "-10", "--timeout", "20"},
                       (work / "ask.log").string());
    ASSERT_NO_FATAL_FAILURE(expect_exit_zero(ask, std::chrono::seconds(40)));
    EXPECT_NE(ask.output().find(reply->text()), std::string::npos) << "CLI and observer got different answers:\n"
                                                                 << ask.output();
    // Channels by the names the replayed CSV gave them (its header), in the reply and in causal-ask's table.
    EXPECT_EQ(reply->channel_names(), (std::vector<std::string>{"bearing1", "bearing2", "bearing3", "bearing4"}));
    for (const char* name : {"bearing1", "bearing2", "bearing3", "bearing4"}) {
      EXPECT_NE(ask.output().find(std::string("\n") + name + " "), std::string::npos) << name << "\n" << ask.output();
    }
    ServiceProcess unknown("causal-ask", {CAUSAL_ASK_BIN, "--domain", d, "--asset-group", "no-such-group",
                                          "--intervene", "2", "--percent", "-10", "--timeout", "20"},
                           (work / "ask_unknown.log").string());
    const auto unknown_code = unknown.wait(std::chrono::seconds(40));
    ASSERT_TRUE(unknown_code.has_value()) << unknown.output();
    EXPECT_EQ(*unknown_code, 4) << unknown.output();
    EXPECT_NE(unknown.output().find("unknown asset group"), std::string::npos) << unknown.output();
    std::printf("[%s] causal-ask printed:\n%s", sc.name, ask.output().c_str());
  }
  EXPECT_EQ(alarm.terminate(), 0) << alarm.output();  // questions answered: no need to wait for its idle exit

  if (learned) {
    // The learned order must put bearing 2 before bearing 1: x12 (2 -> 1 at once) estimated, x21 not.
    const auto names = observer.factor_names_seen(causal_twin::CONDITION_LEVEL);
    auto seen = [&](const char* n) { return std::find(names.begin(), names.end(), n) != names.end(); };
    EXPECT_TRUE(seen("x12")) << estimator.output();
    EXPECT_FALSE(seen("x21")) << estimator.output();
  }
  bool alarm_on_1 = false;
  for (const auto& a : observer.alarms()) {
    EXPECT_GE(a.sample_index(), static_cast<unsigned long long>(kChangeAt)) << "alarm before the change: " << a.reason();
    if (a.channel() == 1 && a.state() == causal_twin::RAISED) alarm_on_1 = true;
  }
  ASSERT_TRUE(alarm_on_1) << "no alarm on bearing 1; alarm log:\n" << alarm.output();
  const auto recs = observer.recommendations();
  bool upstream = false;
  for (const auto& r : recs) {
    std::printf("[%s] recommendation %s: act on %u, target %u, %s effect %.4f [%.4f, %.4f]: %s\n", sc.name,
                r.recommendation_id().c_str(), r.intervene_channel(), r.target_channel(), r.answer_kind().c_str(),
                r.effect_median(), r.effect_low(), r.effect_high(), r.text().c_str());
    EXPECT_FALSE(r.action().empty()) << r.text();  // every alarm event carries an action
    if (r.draws() == 0) {  // an action on the alarmed asset with no model answer behind it
      EXPECT_EQ(r.action_kind(), "act_on_asset") << r.text();
      EXPECT_FALSE(r.reliable()) << r.text();
      continue;
    }
    EXPECT_LE(r.effect_low(), r.effect_median()) << r.text();
    EXPECT_GE(r.effect_high(), r.effect_median()) << r.text();
    if (r.target_channel() == 1 && r.rank() == 1) {
      EXPECT_EQ(r.intervene_channel(), 2) << r.text();
      EXPECT_EQ(r.act_on_channel(), 2) << r.action();
      // The order behind the lever claim: the configured graph, or a stable VAR-LiNGAM order (uniform noise).
      EXPECT_EQ(r.order_source(), learned ? "learned" : "configured") << r.order_confidence();
      EXPECT_TRUE(r.reliable()) << r.text();
      EXPECT_LT(r.effect_median(), 0.0) << r.text();
      upstream = r.intervene_channel() == 2;
    }
  }
  EXPECT_TRUE(upstream) << "no rank-1 recommendation for bearing 1; alarm log:\n" << alarm.output();
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}

INSTANTIATE_TEST_SUITE_P(Estimators, RecommendationUpstream, ::testing::ValuesIn(kScenarios),
                         [](const ::testing::TestParamInfo<Scenario>& p) { return std::string(p.param.name); });
