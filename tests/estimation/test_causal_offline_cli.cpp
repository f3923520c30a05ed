// causal-offline end to end: runs the binary on CSVs written here, checks the output header and values
// (against the library called in-process) and that malformed files give exit code 2 naming file and line.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "causal/estimation/batch_estimation.hpp"
#include "causal/io/numeric_table.hpp"
#include "causal/estimation/kernel_dispatch.hpp"
#include "svar_test_support.hpp"
#include "test_files.hpp"

namespace causal {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string out, err;
};

using causal::test::slurp;

class CausalOfflineCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("causal_offline_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

  Result run(const std::string& args) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = std::string("\"") + CAUSAL_OFFLINE_BIN + "\" " + args + " > \"" + out.string() +
                            "\" 2> \"" + err.string() + "\"";
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  }

  // causal-offline <in> --out <out><args> (args starts with a space).
  Result estimate(const fs::path& in, const fs::path& out, const std::string& args = "") {
    return run("\"" + in.string() + "\" --out \"" + out.string() + "\"" + args);
  }

  fs::path dir_;
};

std::string number(double v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

std::string channels_csv(const Eigen::MatrixXd& y) {
  std::string csv = "alpha,beta,gamma\n";
  for (Eigen::Index n = 0; n < y.rows(); ++n) {
    csv += number(y(n, 0)) + "," + number(y(n, 1)) + "," + number(y(n, 2)) + "\n";
  }
  return csv;
}

// The three channels alpha, beta, gamma (default model spec) and a simulated run of them, noise kNoise.
const estimation::NoiseParams kNoise{2e-5, 0.02, 1.0};

estimation::SvarLayout three_channels() {
  estimation::ModelSpec spec;
  spec.channels = 3;
  return estimation::SvarLayout(spec);
}

test::Simulation simulate_three(int rows, std::uint64_t seed) {
  return test::simulate_svar(three_channels(), {kNoise}, rows, seed);
}

TEST_F(CausalOfflineCli, WritesAllFactorsAndStdDevsMatchingTheLibrary) {
  const estimation::SvarLayout layout = three_channels();
  const test::Simulation sim = simulate_three(200, 31);
  std::string csv = "time,alpha,beta,gamma\n";
  for (int n = 0; n < 200; ++n) {
    csv += std::to_string(n) + "," + number(sim.y(n, 0)) + "," + number(sim.y(n, 1)) + "," + number(sim.y(n, 2)) + "\n";
  }
  const fs::path in = write("in.csv", csv);
  const fs::path out = dir_ / "factors.csv";
  for (const std::string estimator : {"filter", "fixed-lag", "rts"}) {
    SCOPED_TRACE(estimator);
    const Result res =
        estimate(in, out, " --estimator " + estimator + " --lag 7 --q 2e-5 --r 0.02 --p0 1 --no-standardise");
    ASSERT_EQ(res.exit_code, 0) << res.err;
    const auto rows = parse_csv(slurp(out));
    ASSERT_EQ(rows.size(), 201u);
    const std::vector<std::string> expected_header = {
        "n",      "x12",     "x13",     "xL12",    "xL13",    "x21",     "x23",     "xL21",    "xL23",
        "x31",    "x32",     "xL31",    "xL32",    "sd_x12",  "sd_x13",  "sd_xL12", "sd_xL13", "sd_x21",
        "sd_x23", "sd_xL21", "sd_xL23", "sd_x31",  "sd_x32",  "sd_xL31", "sd_xL32"};
    EXPECT_EQ(rows[0], expected_header);
    const estimation::EstimationRun ref = estimator == std::string("filter") ? estimation::run_filter(layout, {kNoise}, sim.y)
                              : estimator == std::string("rts")  ? estimation::run_rts_smoother(layout, {kNoise}, sim.y)
                                                                 : estimation::run_fixed_lag_smoother(layout, {kNoise}, sim.y, {}, 7);
    for (int n = 0; n < 200; n += 13) {
      ASSERT_EQ(rows[n + 1].size(), 25u);
      EXPECT_EQ(rows[n + 1][0], std::to_string(n));
      for (int c = 0; c < 12; ++c) {
        EXPECT_NEAR(std::stod(rows[n + 1][1 + c]), ref.estimates(n, c), 1e-12);
        EXPECT_NEAR(std::stod(rows[n + 1][13 + c]), ref.std_devs(n, c), 1e-12);
      }
    }
  }
  // Automatic noise runs and reports the tuned values.
  const Result tuned = estimate(in, out, " --auto-noise");
  ASSERT_EQ(tuned.exit_code, 0) << tuned.err;
  EXPECT_NE(tuned.err.find("auto-noise: outcome 3"), std::string::npos) << tuned.err;
}

// --format columns: the binary column file holds exactly the numbers of the CSV (bit for bit: both are the
// same run) with the same names and n = i * every, and they are the library's factors.
TEST_F(CausalOfflineCli, ColumnsFormatHoldsExactlyTheCsvNumbers) {
  const estimation::SvarLayout layout = three_channels();
  const test::Simulation sim = simulate_three(300, 41);
  const fs::path in = write("in.csv", channels_csv(sim.y));
  const fs::path out_csv = dir_ / "f.csv", out_cols = dir_ / "f.cols";
  const std::string common = " --estimator filter --q 2e-5 --r 0.02 --p0 1 --no-standardise --every 3";
  ASSERT_EQ(estimate(in, out_csv, common).exit_code, 0);
  const Result res = estimate(in, out_cols, " --format columns" + common);
  ASSERT_EQ(res.exit_code, 0) << res.err;
  // The log names the kernel variant the loader chose (results repeat bit for bit only within one variant).
  EXPECT_NE(res.err.find(std::string("; kernels ") + estimation::kernel_instruction_set() + "\n"), std::string::npos) << res.err;
  const auto rows = parse_csv(slurp(out_csv));
  const io::NumericTable cols = io::read_numeric_columns(out_cols.string());
  ASSERT_EQ(rows.size(), 101u);
  ASSERT_EQ(cols.values.rows(), 100);
  ASSERT_EQ(cols.values.cols(), 24);
  EXPECT_EQ(cols.index_name, "n");
  EXPECT_EQ(cols.index_start, 0);
  EXPECT_EQ(cols.index_step, 3);
  EXPECT_EQ(cols.names, std::vector<std::string>(rows[0].begin() + 1, rows[0].end()));
  estimation::BatchOutput every3;
  every3.every = 3;
  const estimation::EstimationRun ref = estimation::run_filter(layout, {kNoise}, sim.y, {}, every3);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(rows[i + 1][0], std::to_string(3 * i));
    for (int c = 0; c < 24; ++c) {
      double v = 0;
      const std::string& cell = rows[i + 1][1 + c];
      ASSERT_EQ(std::from_chars(cell.data(), cell.data() + cell.size(), v).ec, std::errc());
      ASSERT_EQ(std::memcmp(&v, &cols.values(i, c), sizeof v), 0) << "row " << i << " column " << c;
      const double expect = c < 12 ? ref.estimates(i, c) : ref.std_devs(i, c - 12);
      EXPECT_NEAR(cols.values(i, c), expect, 1e-12);
    }
  }
}

// Scale invariance end to end: 'beta' in other units (x1e6, x1e-9) gives the factors of the unscaled file
// times the exact unit relation x_kj -> x_kj s_k / s_j, with fixed and with tuned noise, never NaN.
TEST_F(CausalOfflineCli, ChannelUnitsDoNotChangeTheFactors) {
  const estimation::SvarLayout layout = three_channels();
  const test::Simulation sim = simulate_three(400, 17);
  const std::vector<std::string> names = layout.factor_names();
  const fs::path base_in = write("base.csv", channels_csv(sim.y));
  for (const std::string noise : {"", " --auto-noise --calibration-samples 200"}) {
    SCOPED_TRACE(noise);
    const fs::path base_out = dir_ / "base_factors.csv";
    const Result base = estimate(base_in, base_out, noise);
    ASSERT_EQ(base.exit_code, 0) << base.err;
    const auto ref = parse_csv(slurp(base_out));
    ASSERT_EQ(ref.size(), 401u);
    for (double f : {1e6, 1e-9}) {
      SCOPED_TRACE(f);
      Eigen::MatrixXd y = sim.y;
      y.col(1) *= f;
      const fs::path in = write("scaled.csv", channels_csv(y));
      const fs::path out = dir_ / "scaled_factors.csv";
      const Result res = estimate(in, out, noise);
      ASSERT_EQ(res.exit_code, 0) << res.err;
      const std::string text = slurp(out);
      EXPECT_EQ(text.find("nan"), std::string::npos);
      const auto rows = parse_csv(text);
      ASSERT_EQ(rows.size(), 401u);
      ASSERT_EQ(rows[0], ref[0]);
      double worst = 0.0;
      for (int c = 0; c < 12; ++c) {
        // names x{k}{j} / xL{k}{j}: channel 2 (beta) as outcome divides by f, as regressor multiplies
        const std::string& nm = names[c];
        const int k = nm[nm.size() - 2] - '0', j = nm[nm.size() - 1] - '0';
        const double u = (k == 2 ? 1.0 / f : 1.0) * (j == 2 ? f : 1.0);
        for (std::size_t n = 1; n < rows.size(); ++n) {
          worst = std::max(worst, std::abs(std::stod(rows[n][1 + c]) * u - std::stod(ref[n][1 + c])));
          worst = std::max(worst, std::abs(std::stod(rows[n][13 + c]) * u - std::stod(ref[n][13 + c])));
        }
      }
      EXPECT_LT(worst, 1e-9);
    }
  }
}

TEST_F(CausalOfflineCli, DeadOrStuckChannelIsRefusedNamingIt) {
  const test::Simulation sim = simulate_three(200, 3);
  for (double level : {0.0, 2.5}) {
    Eigen::MatrixXd y = sim.y;
    y.col(1).setConstant(level);
    const fs::path in = write("dead.csv", channels_csv(y));
    for (const std::string extra : {"", " --auto-noise", " --no-standardise --estimator filter"}) {
      SCOPED_TRACE(extra);
      const Result res = estimate(in, dir_ / "o.csv", extra);
      EXPECT_EQ(res.exit_code, 2);
      EXPECT_NE(res.err.find("dead.csv: channel 2 'beta' is constant over the 200 calibration rows"),
                std::string::npos)
          << res.err;
    }
  }
}

// Raw units at 1e160 overflow the filter: an error exit naming factor, channel, row and file line; never NaN
// with exit 0. Standardised, the same file is estimated normally.
TEST_F(CausalOfflineCli, NonFiniteEstimateExitsNonZeroNamingFactorChannelAndRow) {
  const test::Simulation sim = simulate_three(100, 4);
  const fs::path in = write("huge.csv", channels_csv(sim.y * 1e160));
  const fs::path out = dir_ / "o.csv";
  Result res = estimate(in, out, " --no-standardise --estimator filter");
  EXPECT_EQ(res.exit_code, 1);
  EXPECT_NE(res.err.find("huge.csv:3: factor x12 (outcome channel 1 'alpha', regressor channel 2 'beta') is not "
                         "finite at row 1"),
            std::string::npos)
      << res.err;
  EXPECT_EQ(slurp(out).find("nan"), std::string::npos);
  res = estimate(in, out, " --estimator rts");
  EXPECT_EQ(res.exit_code, 0) << res.err;
  EXPECT_EQ(slurp(out).find("nan"), std::string::npos);
}

// --every K writes samples 0, K, 2K, ... with exactly the values of the full run.
TEST_F(CausalOfflineCli, EveryKWritesTheFullRunsRows) {
  const test::Simulation sim = simulate_three(301, 8);
  const fs::path in = write("in.csv", channels_csv(sim.y));
  const fs::path full = dir_ / "full.csv", dec = dir_ / "dec.csv";
  ASSERT_EQ(estimate(in, full, " --auto-noise").exit_code, 0);
  const Result res = estimate(in, dec, " --auto-noise --every 10");
  ASSERT_EQ(res.exit_code, 0) << res.err;
  const auto f = parse_csv(slurp(full)), d = parse_csv(slurp(dec));
  ASSERT_EQ(f.size(), 302u);
  ASSERT_EQ(d.size(), 32u);  // header + samples 0, 10, ..., 300
  EXPECT_EQ(d[0], f[0]);
  for (std::size_t i = 1; i < d.size(); ++i) EXPECT_EQ(d[i], f[1 + 10 * (i - 1)]) << i;
  EXPECT_EQ(run("\"" + in.string() + "\" --every 0").exit_code, 2);
}

// causal-recorder's conditions CSV (snapshot,time_ns,time_utc before the channels) read from standard input
// gives the factors of the plain channels file: the bookkeeping columns are not channels.
TEST_F(CausalOfflineCli, ReadsARecorderConditionsCsvFromStandardInput) {
  const test::Simulation sim = simulate_three(120, 5);
  const fs::path plain = write("plain.csv", channels_csv(sim.y));
  std::string recorded;
  std::istringstream lines(channels_csv(sim.y));
  std::string line;
  for (long n = -1; std::getline(lines, line); ++n) {
    recorded += n < 0 ? "snapshot,time_ns,time_utc," + line + "\n"
                      : std::to_string(n) + "," + std::to_string(1076581959000000000LL + n * 600000000000LL) +
                            ",2004-02-12 10:32:39," + line + "\n";
  }
  const fs::path rec = write("conditions_g_meanabs.csv", recorded);
  const fs::path plain_out = dir_ / "plain_factors.csv", rec_out = dir_ / "rec_factors.csv";
  ASSERT_EQ(estimate(plain, plain_out, " --auto-noise").exit_code, 0);
  const Result res = run("- --out \"" + rec_out.string() + "\" --auto-noise < \"" + rec.string() + "\"");
  ASSERT_EQ(res.exit_code, 0) << res.err;
  const auto a = parse_csv(slurp(plain_out)), b = parse_csv(slurp(rec_out));
  ASSERT_EQ(a.size(), 121u);
  ASSERT_EQ(b.size(), a.size());
  // The recorded file has a time column, which the output may carry in front: compare the factor columns.
  ASSERT_GE(b[0].size(), a[0].size());
  const std::size_t shift = b[0].size() - a[0].size();
  for (std::size_t r = 0; r < a.size(); ++r) {
    ASSERT_EQ(b[r].size(), a[r].size() + shift) << r;
    for (std::size_t c = 0; c < a[r].size(); ++c) EXPECT_EQ(b[r][c + shift], a[r][c]) << r << "," << c;
  }
  const Result version = run("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out, std::string(CAUSAL_TWIN_VERSION) + "\n");
}

TEST_F(CausalOfflineCli, MalformedFilesExitWithCode2AndNameTheLine) {
  const fs::path text = write("text.csv", "a,b,c\n1,2,3\n1,oops,3\n");
  Result res = run("\"" + text.string() + "\"");
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("text.csv:3"), std::string::npos) << res.err;

  const fs::path nan = write("nan.csv", "a,b,c\n1,2,3\n\n4,5,6\n7,nan,9\n");  // blank line 3 counts
  res = run("\"" + nan.string() + "\"");
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("nan.csv:5"), std::string::npos) << res.err;

  const fs::path ragged = write("ragged.csv", "a,b,c\n1,2,3\n4,5\n");
  res = run("\"" + ragged.string() + "\"");
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("ragged.csv:3"), std::string::npos) << res.err;

  const fs::path one = write("one.csv", "a\n1\n2\n");
  res = run("\"" + one.string() + "\"");
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("at least 2 channel"), std::string::npos) << res.err;

  res = run("\"" + (dir_ / "missing.csv").string() + "\"");
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("missing.csv"), std::string::npos) << res.err;

  res = run("\"" + text.string() + "\" --estimator nonsense");
  EXPECT_EQ(res.exit_code, 2);
}

}  // namespace
}  // namespace causal
