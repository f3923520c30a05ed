// CPU of one alarm's advice against the asset group's width (plain program, a table; docs/advice.md, "Cost of the
// advice"). IMS test 2 with every bearing copied 1, 2 and 5 times (4, 8, 20 channels; tests/support
// make_replicated_variant, seed 32) through causal-estimator's AssetPipeline with the shipped
// deploy/config/estimator.yaml; every condition-level filter observation goes to the recommender's Advisor (the
// shipped draws and max_candidates), and at the decision points the advice for bearing 1's first channel is
// computed twice in the same run, interleaved: with the candidates' draws shared (as shipped) and one candidate
// at a time (analysis::DrawSharing::per_query, the way before). Both must give the same items, bit for bit
// (texts, medians, intervals, unstable draws, the healthy-reference verdict); a difference exits 1.
//   build/tests/bench/causal_bench_advice_cost [--repeat N (1)] [--widths 1,2,5] [--shared-only (for a profiler)]
#include "causal/advice/advisor.hpp"
#include "causal/pipeline/estimator_params.hpp"
#include "ims_variants.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace causal;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// IMS test 2's degradation alarm events on bearing 1 (first raise, escalations) and one late point.
const std::vector<std::size_t> kDecisions = {541, 700, 900, 969};
constexpr std::size_t kLearning = 110;  // baseline learned (calibration window 100 + warm-up)
constexpr std::size_t kDegraded = 530;  // a degradation alarm open from here on (the reference is captured before)

// Every condition-level filter observation up to the last decision point, as the recommender assembles them.
std::vector<advice::ModelObservation> observations(const pipeline::AssetPipelineParams& params,
                                                   const testing::Variant& v) {
  pipeline::AssetPipeline pipe(params);
  pipeline::PipelineOutput out;
  std::vector<advice::ModelObservation> obs;
  for (Eigen::Index i = 0; i <= static_cast<Eigen::Index>(kDecisions.back()); ++i) {
    out.clear();
    const auto check = pipe.feed_condition(v.values.row(i).transpose(), static_cast<std::uint64_t>(i), i == 0,
                                           v.time_ns[static_cast<std::size_t>(i)], out);
    if (!check.ok) {
      std::fprintf(stderr, "refused: %s\n", check.problem.c_str());
      std::exit(1);
    }
    if (pipe.condition_stream() == nullptr) continue;
    const auto& layout = pipe.condition_stream()->layout();
    advice::ModelObservation a;
    a.asset_group = "ims2";
    a.channel_names = v.channel_names;
    a.factor_names = layout.factor_names();
    a.lag_order = layout.lag_order();
    a.observation.index = static_cast<std::uint64_t>(i);
    a.observation.time_ns = v.time_ns[static_cast<std::size_t>(i)];
    a.observation.features = v.values.row(i).transpose();
    Eigen::VectorXd f(layout.total_factors()), sd(layout.total_factors());
    Eigen::Index at = 0;
    for (const auto& r : out.condition_reports) {
      if (r.kind != pipeline::EstimateKind::Filter || r.sample_index != static_cast<std::uint64_t>(i)) continue;
      f.segment(at, r.factors.size()) = r.factors;
      sd.segment(at, r.factors.size()) = r.std_devs;
      at += r.factors.size();
      a.covariance_blocks.push_back(r.covariance);
    }
    if (at != layout.total_factors()) continue;
    a.observation.factors = f;
    a.observation.factor_std = sd;
    obs.push_back(std::move(a));
  }
  return obs;
}

// Everything an advice item publishes, printed at full precision: equal strings = the same advice.
std::string fingerprint(const std::vector<advice::AdviceItem>& items, const std::string& why) {
  std::ostringstream s;
  s.precision(17);
  s << why << '\n';
  for (const auto& a : items) {
    s << a.rank << ' ' << a.intervene << ' ' << a.delta << ' ' << a.immediate << ' ' << a.effect << ' ' << a.lower << ' '
      << a.upper << ' ' << a.percent << ' ' << a.reliable << ' ' << a.diag.kind << ' ' << a.diag.unstable_draws << ' '
      << a.diag.spectral_radius << ' ' << a.reference << ' ' << a.reference_percent << ' ' << a.text << '\n';
  }
  return s.str();
}

struct Cost {
  double seconds = 0.0;
  std::string fingerprint;
};

Cost advise_once(const advice::Advisor& advisor, const Eigen::VectorXd& baseline) {
  std::string why;
  const double t0 = cpu_seconds();
  const auto items = advisor.evaluate("ims2", 0, baseline, why);
  return Cost{cpu_seconds() - t0, fingerprint(items, why)};
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 1;
  bool shared_only = false;
  std::vector<int> widths = {1, 2, 5};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::printf("causal_bench_advice_cost [--repeat N (1)] [--widths 1,2,5] [--shared-only]: CPU of one alarm's advice on IMS test 2 "
                  "with each bearing copied 1, 2 and 5 times (4, 8, 20 channels), candidates' draws shared against one "
                  "candidate at a time, in the same run; exits 1 when the two advise differently\n");
      return 0;
    }
    if (a == "--repeat" && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
      if (repeat < 1) repeat = 0;
    } else if (a == "--shared-only") {
      shared_only = true;  // under a profiler: only the shipped way
    } else if (a == "--widths" && i + 1 < argc) {
      widths.clear();
      std::stringstream list(argv[++i]);
      for (std::string w; std::getline(list, w, ',');) widths.push_back(std::atoi(w.c_str()));
    } else {
      repeat = 0;
    }
    if (repeat == 0 || widths.empty() || *std::min_element(widths.begin(), widths.end()) < 1) {
      std::fprintf(stderr, "usage: causal_bench_advice_cost [--repeat N >= 1] [--widths 1,2,5 (copies per bearing)]\n");
      return 2;
    }
  }
  const std::string deploy = CAUSAL_TWIN_DEPLOY_DIR;
  const auto params = pipeline::load_estimator_params(deploy + "/config/estimator.yaml");
  const auto base = testing::read_base_run(deploy + "/data/ims2-features/merged_dataset_BearingTest_2.csv");
  std::printf("channels decision candidates per_query_cpu_ms shared_cpu_ms ratio same_advice (best of %d)\n", repeat);
  bool all_same = true;
  for (const int copies : widths) {
    const auto v = testing::make_replicated_variant(base, copies, 32);
    const auto obs = observations(params, v);
    advice::AdvisorParams shared_params, per_query_params;
    per_query_params.draw_sharing = analysis::DrawSharing::per_query;
    const Eigen::Index g = v.values.cols();
    Eigen::VectorXd baseline(g);
    for (Eigen::Index k = 0; k < g; ++k) baseline[k] = std::exp(v.values.col(k).head(100).array().log().mean());
    advice::Advisor shared(shared_params), per_query(per_query_params);
    double total_shared = 0.0, total_per_query = 0.0;
    std::size_t next = 0;
    for (const auto& a : obs) {
      for (advice::Advisor* adv : {&shared, &per_query}) {
        adv->update(a);
        adv->set_health("ims2", a.observation.index < kLearning, a.observation.index >= kDegraded);
      }
      if (next >= kDecisions.size() || a.observation.index != kDecisions[next]) continue;
      ++next;
      Cost best_shared, best_per_query;
      for (int r = 0; r < repeat; ++r) {
        const Cost p = shared_only ? Cost{} : advise_once(per_query, baseline);
        const Cost s = advise_once(shared, baseline);
        if (r == 0 || p.seconds < best_per_query.seconds) best_per_query = p;
        if (r == 0 || s.seconds < best_shared.seconds) best_shared = s;
      }
      const bool same = best_shared.fingerprint == best_per_query.fingerprint;
      all_same = all_same && same;
      const auto items = static_cast<long>(std::count(best_shared.fingerprint.begin(), best_shared.fingerprint.end(), '\n')) - 1;
      total_shared += best_shared.seconds;
      total_per_query += best_per_query.seconds;
      std::printf("%8lld %8llu %10ld %16.1f %13.1f %5.2f %s\n", static_cast<long long>(g),
                  static_cast<unsigned long long>(a.observation.index), items, 1e3 * best_per_query.seconds,
                  1e3 * best_shared.seconds, best_per_query.seconds / best_shared.seconds, same ? "yes" : "NO");
      if (!same) std::printf("per query:\n%sshared:\n%s", best_per_query.fingerprint.c_str(), best_shared.fingerprint.c_str());
    }
    std::printf("%8lld %8s %10s %16.1f %13.1f %5.2f (mean per advice)\n", static_cast<long long>(g), "all", "",
                1e3 * total_per_query / static_cast<double>(next), 1e3 * total_shared / static_cast<double>(next),
                total_per_query / total_shared);
  }
  return all_same || shared_only ? 0 : 1;
}
