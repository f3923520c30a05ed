// End-to-end check of the causal-whatif executable on a CSV simulated from a known structural VAR.
#include <gtest/gtest.h>

#include <causal/analysis/effect_units.hpp>
#include <causal/analysis/intervention.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "svar_sim.hpp"

using namespace causal::analysis;
using namespace causal::analysis::test;

namespace {

const std::vector<std::string> kNames{"bearing 1", "bearing 2", "bearing 3", "bearing 4"};

struct CliRun {
  int exit_code = -1;
  std::string out;  // stdout + stderr
};

CliRun run_cli(const std::string& args) {
  const std::string cmd = std::string(CAUSAL_WHATIF_BIN) + " " + args + " 2>&1";
  CliRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe) != nullptr) r.out += buf;
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

struct Scenario {
  TrueSvar truth;
  Eigen::MatrixXd e;
  Eigen::MatrixXd y;  // as written (offset 0.1)
  std::string dir;
  std::string csv;
};

Scenario& scenario() {
  static Scenario s = [] {
    Scenario sc;
    std::mt19937_64 rng(123);
    sc.truth = random_svar(rng, 4, 1);
    const int burn = 200, n = 3000;
    const Eigen::MatrixXd e_all = draw_noise(rng, n + burn, Eigen::VectorXd::Constant(4, 0.01), NoiseKind::laplace);
    sc.y = (simulate(sc.truth, e_all).bottomRows(n).array() + 0.1).matrix();
    sc.e = e_all.bottomRows(n);
    sc.dir = (std::filesystem::temp_directory_path() / ("causal_whatif_test_" + std::to_string(::getpid()))).string();
    std::filesystem::create_directories(sc.dir);
    sc.csv = sc.dir + "/channels.csv";
    std::ofstream f(sc.csv);
    f << "n";
    for (const auto& name : kNames) f << "," << name;
    f << "\n";
    f.precision(17);
    for (int r = 0; r < n; ++r) {
      f << r;
      for (int c = 0; c < 4; ++c) f << "," << sc.y(r, c);
      f << "\n";
    }
    return sc;
  }();
  return s;
}

// Removes the scenario's temporary folder at the end of the run.
class CleanUp : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(scenario().dir, ec);
  }
};
const auto* const kCleanUp = ::testing::AddGlobalTestEnvironment(new CleanUp);

// Parses the table row of `name`: immediate, lower, upper, steady/cumulative, lower, upper.
std::vector<double> table_row(const std::string& out, const std::string& name) {
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(name + " ", 0) != 0) continue;
    std::istringstream fields(line.substr(name.size()));
    std::vector<double> v;
    double x;
    while (fields >> x) v.push_back(x);
    if (v.size() == 6) return v;
  }
  return {};
}

// Sustained is the default (as in causal-ask); the CSV comes on standard input here ("--csv -").
TEST(WhatifCli, SustainedShiftMatchesTrueSystem) {
  const Scenario& s = scenario();
  const std::string model = " --self-lags --lingam --calibration 1000 --intervene 3 --delta -0.02";
  const CliRun r = run_cli("--csv -" + model + " < " + s.csv);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("sustained from now on"), std::string::npos) << r.out;
  const CliRun explicit_sustained = run_cli("--csv " + s.csv + model + " --sustained");
  EXPECT_EQ(explicit_sustained.out, r.out);
  const CliRun impulse = run_cli("--csv " + s.csv + model + " --impulse");
  ASSERT_EQ(impulse.exit_code, 0) << impulse.out;
  EXPECT_NE(impulse.out.find("for one sample (impulse)"), std::string::npos) << impulse.out;
  // The estimated order is printed with names and equals the true one.
  std::string order;
  for (std::size_t i = 0; i < s.truth.order.size(); ++i) order += (i ? " -> " : "") + kNames[s.truth.order[i]];
  EXPECT_NE(r.out.find("VAR-LiNGAM causal order (estimated on rows 0..999): " + order), std::string::npos) << r.out;
  StructuralModel m;
  m.a0 = s.truth.a0;
  m.lags = s.truth.lags;
  InterventionQuery q;
  q.channel = 2;
  q.delta = -0.02;
  const InterventionEffect truth = predict_intervention(m, q);
  ASSERT_EQ(truth.status, AnalysisStatus::ok);
  for (int k = 0; k < 4; ++k) {
    const std::vector<double> row = table_row(r.out, kNames[k]);
    ASSERT_EQ(row.size(), 6u) << kNames[k] << "\n" << r.out;
    EXPECT_LE(row[1], row[0]);
    EXPECT_GE(row[2], row[0]);
    // 3000 samples, |delta| = 0.02: the estimate is within 10% of delta of the truth.
    EXPECT_NEAR(row[0], truth.immediate(k), 0.002) << kNames[k];
    EXPECT_NEAR(row[3], truth.steady_state(k), 0.002) << kNames[k];
  }
}

TEST(WhatifCli, CounterfactualWritesSeries) {
  const Scenario& s = scenario();
  const std::string out = s.dir + "/cf.csv";
  const CliRun r = run_cli("--csv " + s.csv + " --self-lags --lingam --calibration 1000 --counterfactual --channel \"bearing 3\" "
                    "--hold 0.1 --from 2000 --to 2099 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  // True counterfactual: the same noise with bearing 3 forced to 0 (= 0.1 - offset) over the window.
  Eigen::MatrixXd forced = no_force(3000, 4);
  forced.block(2000, 2, 100, 1).setZero();
  // Re-simulate from the written data's start: simulate() starts from zero history, so compare deviations
  // from the observed series, which do not depend on the start.
  const Eigen::MatrixXd base = simulate(s.truth, s.e);
  const Eigen::MatrixXd cf = simulate(s.truth, s.e, &forced);
  std::ifstream f(out);
  std::string line;
  ASSERT_TRUE(std::getline(f, line));
  EXPECT_EQ(line, "n,bearing 1,bearing 2,bearing 3,bearing 4,bearing 1 (observed),bearing 2 (observed),"
                  "bearing 3 (observed),bearing 4 (observed)");
  int rows = 0;
  double worst = 0.0, scale = 0.0;
  while (std::getline(f, line)) {
    std::istringstream fields(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(fields, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 9u);
    const int n = static_cast<int>(v[0]);
    EXPECT_EQ(n, 2000 + rows);
    EXPECT_EQ(v[3], 0.1);  // held exactly
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(v[5 + k], s.y(n, k));  // observed, bit-exact round trip
      const double predicted_change = v[1 + k] - v[5 + k];
      const double true_change = cf(n, k) - base(n, k);
      worst = std::max(worst, std::abs(predicted_change - true_change));
      scale = std::max(scale, std::abs(true_change));
    }
    ++rows;
  }
  EXPECT_EQ(rows, 100);
  EXPECT_LT(worst, 0.1 * scale) << "worst " << worst << " scale " << scale;
}

TEST(WhatifCli, RecommendsInPlainLanguage) {
  const Scenario& s = scenario();
  const CliRun r = run_cli("--csv " + s.csv + " --self-lags --lingam --calibration 1000 --recommend 4 --unit g --baseline-rows 1000 "
                    "--current-rows 1 --fraction 1");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("recommendations for bearing 4"), std::string::npos) << r.out;
}

// The answer lines (after "answer ("): the other channels, one line each.
std::vector<std::string> answer_lines(const std::string& out) {
  std::istringstream in(out);
  std::string line;
  std::vector<std::string> lines;
  bool in_answer = false;
  while (std::getline(in, line)) {
    if (line.rfind("answer (", 0) == 0) in_answer = true;
    else if (in_answer && line.rfind("  ", 0) == 0) lines.push_back(line);
  }
  return lines;
}

// The live twin's decision (analysis::effect_unknown_reason) on every answer line: a shift of 20 times the
// levels (~0.1) moves the downstream channels by thousands of percent, which no figure states; a CSV whose
// levels are not positive has no percent to state, and the line says so instead of a number.
TEST(WhatifCli, UnknownWithItsReasonAndNoFigureBeyondTheCap) {
  const Scenario& s = scenario();
  const std::string model = " --self-lags --lingam --calibration 1000 --intervene 3 --delta 2";
  const CliRun r = run_cli("--csv " + s.csv + model);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto lines = answer_lines(r.out);
  ASSERT_EQ(lines.size(), 3u) << r.out;
  int unknown = 0;
  for (const auto& l : lines) {
    EXPECT_EQ(l.find("> +1000"), std::string::npos) << l;
    if (l.find("effect unknown (the 90 % interval") != std::string::npos) ++unknown;
  }
  EXPECT_GE(unknown, 1) << r.out;  // at least one channel lies downstream of bearing 3 in the true order
  const std::string shifted = s.dir + "/negative.csv";
  {
    std::ofstream f(shifted);
    f << "n,a,b,c,d\n";
    f.precision(17);
    for (int i = 0; i < s.y.rows(); ++i) {
      f << i;
      for (int c = 0; c < 4; ++c) f << "," << s.y(i, c) - 1.0;
      f << "\n";
    }
  }
  const CliRun neg = run_cli("--csv " + shifted + model);
  ASSERT_EQ(neg.exit_code, 0) << neg.out;
  const auto neg_lines = answer_lines(neg.out);
  ASSERT_EQ(neg_lines.size(), 3u) << neg.out;
  for (const auto& l : neg_lines)
    EXPECT_NE(l.find("effect unknown (the level at row 2999 is not positive"), std::string::npos) << l;
}

// IMS test 2 (the four bearings' mean |x|, log taken: the live twin's log_transform), sustained -10 % on a bearing
// at rows where the model sits near or past a unit root: every answer line makes the live twin's decision
// (analysis::effect_unknown_reason on the percent interval, recomputed here from the line's own interval in the
// CSV's units), says "effect unknown (<reason>)" where it is unknown, and states no figure beyond +-1000 %.
TEST(WhatifCli, ImsTest2UnknownWhereTheLiveTwinSaysSoAndNoFigureBeyondTheCap) {
  const std::string csv = scenario().dir + "/ims2_log.csv";
  {
    std::ifstream in(std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/merged_dataset_BearingTest_2.csv");
    ASSERT_TRUE(in.good());
    std::ofstream out(csv);
    out.precision(17);
    std::string line;
    std::getline(in, line);
    out << "snapshot,Bearing1,Bearing2,Bearing3,Bearing4\n";
    for (int row = 0; std::getline(in, line); ++row) {
      std::istringstream cells(line);
      std::string cell;
      std::getline(cells, cell, ',');  // the time stamp
      out << row;
      while (std::getline(cells, cell, ',')) out << "," << std::log(std::stod(cell));
      out << "\n";
    }
  }
  int unknown = 0, known = 0;
  for (const auto& [at, channel] : std::vector<std::pair<int, int>>{{648, 2}, {648, 4}, {744, 3}, {900, 1}}) {
    const CliRun r = run_cli("--csv " + csv + " --lingam --calibration 100 --log-levels --at " + std::to_string(at) +
                             " --intervene " + std::to_string(channel) + " --delta " + std::to_string(std::log(0.9)));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto lines = answer_lines(r.out);
    ASSERT_EQ(lines.size(), 3u) << r.out;
    for (const auto& l : lines) {
      SCOPED_TRACE(l);
      const auto open = l.rfind("(");
      double point = 0.0, lo = 0.0, hi = 0.0;
      ASSERT_EQ(std::sscanf(l.c_str() + open, "(%lf [%lf, %lf] in the CSV's units)", &point, &lo, &hi), 3);
      const std::string why = effect_unknown_reason(100.0 * std::expm1(lo), 100.0 * std::expm1(hi), 0.9);
      if (!why.empty()) {
        ++unknown;
        // The same reason (its figure, e.g. the level factor, is recomputed here from 6 printed digits).
        EXPECT_NE(l.find("effect unknown (" + why.substr(0, 33)), std::string::npos) << why;
        continue;
      }
      ++known;
      EXPECT_EQ(l.find("effect unknown"), std::string::npos);
      // The stated figures: "<effect> % [<lower>, <upper>] (90 %)".
      double e = 0.0, a = 0.0, b = 0.0;
      const auto colon = l.find(": ");
      ASSERT_EQ(std::sscanf(l.c_str() + colon, ": %lf %% [%lf, %lf]", &e, &a, &b), 3);
      for (double v : {e, a, b}) EXPECT_LE(std::abs(v), 1000.0);
    }
  }
  EXPECT_GE(unknown, 3);  // 648 x 2 and 744 x 3 reach beyond +1000 %, 648 x 4 spans a factor of 10^8 in level
  EXPECT_GE(known, 3);
}

TEST(WhatifCli, ClearErrors) {
  const Scenario& s = scenario();
  CliRun r = run_cli("--csv " + s.csv + " --intervene 9 --delta 1");
  EXPECT_EQ(r.exit_code, 2);  // bad input: 2, as every tool
  EXPECT_NE(r.out.find("unknown channel '9'"), std::string::npos) << r.out;
  r = run_cli("--csv " + s.csv + " --graph \"1->2, 2->1\" --intervene 1 --delta 1");
  EXPECT_EQ(r.exit_code, 2);  // bad input: 2, as every tool
  EXPECT_NE(r.out.find("cycle: bearing 1 -> bearing 2 -> bearing 1"), std::string::npos) << r.out;
  r = run_cli("--csv " + s.dir + "/missing.csv");
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli("--csv " + s.csv + " --intervene 1");  // --delta missing
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli("--csv " + s.csv + " --counterfactual --channel 1 --hold 0 --from 0 --to 10");
  EXPECT_EQ(r.exit_code, 2);  // bad input: 2, as every tool
  EXPECT_NE(r.out.find("--from/--to"), std::string::npos) << r.out;
  r = run_cli("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("VAR-LiNGAM"), std::string::npos);
  r = run_cli("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, std::string(CAUSAL_TWIN_VERSION) + "\n");
}

}  // namespace
