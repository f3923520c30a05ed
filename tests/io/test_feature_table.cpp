#include "causal/io/feature_table.hpp"

#include <gtest/gtest.h>

#include "causal/io/input_error.hpp"
#include "causal/io/time_format.hpp"
#include "io_test_util.hpp"
#include "matrix_asserts.hpp"

using causal::io::FeatureTable;
using causal::io::InputError;
using causal::io::read_feature_table;
using causal::io::test::fixture;
using causal::io::test::TempDir;

namespace {

constexpr std::int64_t kTenMin = 600LL * 1'000'000'000;
const std::int64_t kRunStart = causal::io::utc_to_ns(2004, 2, 12, 10, 32, 39);

InputError expect_input_error(const std::string& path, const std::string& suffix = "") {
  return causal::io::test::input_error_of(path, [&] { read_feature_table(path, suffix); });
}

using causal::io::test::contains;

// Checks the facts the IMS README states about the two test-2 tables in `folder`.
void check_real_tables(const std::string& folder) {
  const FeatureTable merged = read_feature_table(folder + "/merged_dataset_BearingTest_2.csv");
  ASSERT_EQ(merged.values.rows(), 984);
  ASSERT_EQ(merged.values.cols(), 4);
  EXPECT_EQ(merged.channel_names, (std::vector<std::string>{"Bearing 1", "Bearing 2", "Bearing 3", "Bearing 4"}));
  ASSERT_EQ(merged.time_ns.size(), 984u);
  // Index i is the start + 10 i minutes, no gaps.
  for (std::size_t i = 0; i < merged.time_ns.size(); ++i) {
    ASSERT_EQ(merged.time_ns[i], kRunStart + static_cast<std::int64_t>(i) * kTenMin) << i;
  }
  Eigen::Index arg = 0;
  const double b1_max = merged.values.col(0).maxCoeff(&arg);
  EXPECT_NEAR(b1_max, 0.453335, 5e-7);
  EXPECT_EQ(causal::io::format_utc(merged.time_ns[static_cast<std::size_t>(arg)]), "2004-02-19 05:42:39");
  EXPECT_NEAR(merged.values.col(0).head(100).mean(), 0.0612, 5e-5);  // "averages 0.0612 over the first 100"

  const FeatureTable rms = read_feature_table(folder + "/derived_per_file_stats_all984.csv", "_rms");
  ASSERT_EQ(rms.values.rows(), 984);
  EXPECT_EQ(rms.channel_names, (std::vector<std::string>{"bearing1", "bearing2", "bearing3", "bearing4"}));
  EXPECT_EQ(rms.time_ns, merged.time_ns);
  // README: bearing-1 RMS 0.0015 to 0.725; the last running file (index 981) has RMS 0.484.
  EXPECT_NEAR(rms.values.col(0).maxCoeff(), 0.725, 5e-4);
  EXPECT_NEAR(rms.values.col(0).minCoeff(), 0.0015, 5e-5);
  EXPECT_NEAR(rms.values(981, 0), 0.484, 5e-4);

  const FeatureTable kurt = read_feature_table(folder + "/derived_per_file_stats_all984.csv", "_kurtosis");
  EXPECT_NEAR(kurt.values(981, 0), 7.9, 0.05);  // "bearing-1 RMS 0.484, kurtosis 7.9"
  EXPECT_NEAR(kurt.values.col(0).maxCoeff(), 17.1, 0.05);

  // Independent cross-check of two third-party/derived tables: merged = mean |x| over rows 2..20480,
  // derived = over all rows; the README states they differ by at most 2.4e-5.
  const FeatureTable meanabs = read_feature_table(folder + "/derived_per_file_stats_all984.csv", "_meanabs");
  ASSERT_MATRIX_NEAR(meanabs.values, merged.values, 2.5e-5);
}

}  // namespace

TEST(FeatureTable, MergedStyleFixture) {
  const FeatureTable t = read_feature_table(fixture("feature_table_merged_style.csv"));
  EXPECT_EQ(t.channel_names, (std::vector<std::string>{"Bearing 1", "Bearing 2", "Bearing 3", "Bearing 4"}));
  EXPECT_EQ(t.time_ns, (std::vector<std::int64_t>{kRunStart, kRunStart + kTenMin, kRunStart + 2 * kTenMin}));
  Eigen::MatrixXd expect(3, 4);
  expect << 0.058, 0.071, 0.083, 0.043, 0.059, 0.074, 0.084, 0.044, 0.060, 0.075, 0.085, 0.045;
  ASSERT_MATRIX_NEAR(t.values, expect, 0.0);
}

TEST(FeatureTable, DerivedStyleFixtureBySuffix) {
  const std::string p = fixture("feature_table_derived_style.csv");
  const FeatureTable rms = read_feature_table(p, "_rms");
  EXPECT_EQ(rms.channel_names, (std::vector<std::string>{"bearing1", "bearing2"}));
  EXPECT_EQ(rms.time_ns.size(), 3u);
  EXPECT_EQ(rms.time_ns[2], kRunStart + 2 * kTenMin);
  Eigen::MatrixXd expect(3, 2);
  expect << 0.074, 0.090, 0.075, 0.093, 0.076, 0.094;
  ASSERT_MATRIX_NEAR(rms.values, expect, 0.0);
  const FeatureTable k = read_feature_table(p, "_kurtosis");
  EXPECT_EQ(k.values(1, 1), 3.2);
  // Without a suffix every value column is a channel ("file" and "timestamp" are bookkeeping).
  const FeatureTable all = read_feature_table(p);
  EXPECT_EQ(all.values.cols(), 6);
  EXPECT_EQ(all.channel_names.front(), "bearing1_meanabs");
}

TEST(FeatureTable, ImsNameTimestampsAndNumericColumnNames) {
  // The bingblackbean copy of the merged table: index YYYY.MM.DD.hh.mm.ss, columns 0..3.
  TempDir dir;
  const auto p = dir.write("b.csv", ",0,1,2,3\n2004.02.12.10.32.39,1,2,3,4\n2004.02.12.10.42.39,5,6,7,8\n");
  const FeatureTable t = read_feature_table(p);
  EXPECT_EQ(t.channel_names, (std::vector<std::string>{"0", "1", "2", "3"}));
  EXPECT_EQ(t.time_ns, (std::vector<std::int64_t>{kRunStart, kRunStart + kTenMin}));
  EXPECT_EQ(t.values(1, 3), 8.0);
}

TEST(FeatureTable, Errors) {
  TempDir dir;
  struct Case {
    const char* content;
    const char* suffix;
    std::size_t line;
    const char* part;
  };
  const Case cases[] = {
      {"", "", 0, "empty"},
      {"t,a\n", "", 0, "no data rows"},
      {"t\n2004-02-12 10:32:39\n", "", 1, "no channel"},
      {"t,a_rms\n2004-02-12 10:32:39,1\n", "_kurtosis", 1, "_kurtosis"},
      {"t,a\n2004-02-12 10:32:39,1\n2004-02-12 10:42:39\n", "", 3, "ragged"},
      {"t,a\n2004-02-12 10:32:39,1\nyesterday,2\n", "", 3, "bad time"},
      {"t,a\n2004-02-12 10:32:39,1\n2004-02-12 10:32:39,2\n", "", 3, "strictly increasing"},
      {"t,a\n2004-02-12 10:42:39,1\n2004-02-12 10:32:39,2\n", "", 3, "strictly increasing"},
      {"t,a\n2004-02-12 10:32:39,1\n2004-02-12 10:42:39,x\n", "", 3, "not a number"},
      {"t,a\n2004-02-12 10:32:39,nan\n", "", 2, "non-finite"},
      {"t,a,b_rms\n2004-02-12 10:32:39,junk,inf\n", "_rms", 2, "non-finite"},
  };
  for (const Case& c : cases) {
    const auto p = dir.write("e.csv", c.content);
    const InputError e = expect_input_error(p, c.suffix);
    EXPECT_EQ(e.line(), c.line) << c.content << " -> " << e.what();
    EXPECT_TRUE(contains(e.what(), c.part)) << c.content << " -> " << e.what();
  }
  // Columns not selected by the suffix are never parsed ("junk" above did not trigger the error).
  const auto ok = dir.write("ok.csv", "t,a,b_rms\n2004-02-12 10:32:39,junk,1.5\n");
  EXPECT_EQ(read_feature_table(ok, "_rms").values(0, 0), 1.5);
}

TEST(FeatureTable, ShippedCopiesMatchReadme) {
  // deploy/data/ims2-features is part of the repo: always checked.
  check_real_tables(causal::io::test::deploy_data("ims2-features"));
}

TEST(FeatureTable, SharedTablesMatchReadme) {
  if (!causal::io::test::shared_available()) {
    GTEST_SKIP() << "full IMS data not found at " << causal::io::test::shared_ims2()
                 << " (set -DCAUSAL_TWIN_SHARED_DIR=<shared folder>)";
  }
  check_real_tables(causal::io::test::shared_ims2());
}

// causal-recorder's conditions_<group>_<feature>.csv as a merged-style table (no suffix): the channels are
// the columns after snapshot,time_ns,time_utc, the time is time_ns exactly; also from standard input.
TEST(FeatureTable, ReadsRecorderConditionsFileAndStdin) {
  TempDir dir;
  const std::string path = dir.write("conditions_ims2-shaft1_meanabs.csv",
                                     "snapshot,time_ns,time_utc,bearing1,bearing2,bearing3\n"
                                     "0,1076581959000000000,2004-02-12 10:32:39,0.06,0.07,0.08\n"
                                     "1,1076582559000000001,2004-02-12 10:42:39,0.16,0.17,0.18\n");
  for (const std::string& source : {path, std::string("-")}) {
    if (source == "-") {
      ASSERT_NE(std::freopen(path.c_str(), "r", stdin), nullptr);
    }
    // The recorder's file holds one feature: a suffix (as causal-alarm-eval --feature-name meanabs gives) is moot.
    const FeatureTable t = read_feature_table(source, "_meanabs");
    ASSERT_EQ(t.channel_names, (std::vector<std::string>{"bearing1", "bearing2", "bearing3"})) << source;
    ASSERT_EQ(t.time_ns, (std::vector<std::int64_t>{kRunStart, kRunStart + kTenMin + 1})) << source;
    ASSERT_EQ(t.values.rows(), 2);
    EXPECT_EQ(t.values(0, 0), 0.06);
    EXPECT_EQ(t.values(1, 2), 0.18);
  }
}

// A table as it is: several features per channel only when every column is <channel>_<known feature>
// with two features or more; any other names are channels.
TEST(FeatureTable, PerFeatureSuffixTellsDerivedFromMergedTables) {
  using causal::io::per_feature_suffix;
  const FeatureTable derived = read_feature_table(fixture("feature_table_derived_style.csv"));
  EXPECT_EQ(derived.channel_names.size(), 6u) << "read without a suffix: every column";
  EXPECT_EQ(per_feature_suffix(derived, "meanabs"), "_meanabs");
  EXPECT_EQ(per_feature_suffix(derived, "kurtosis"), "_kurtosis");
  EXPECT_THROW(per_feature_suffix(derived, "peak"), std::invalid_argument);
  EXPECT_EQ(per_feature_suffix(read_feature_table(fixture("feature_table_merged_style.csv")), "meanabs"), "");
  FeatureTable named;
  named.channel_names = {"Bearing 1 C1", "Bearing 1 C2"};
  EXPECT_EQ(per_feature_suffix(named, "meanabs"), "");
  named.channel_names = {"pump_in", "pump_out"};  // '_' in a channel name, not a feature
  EXPECT_EQ(per_feature_suffix(named, "meanabs"), "");
  named.channel_names = {"bearing1_rms", "bearing2_rms"};  // one feature: its columns are the channels
  EXPECT_EQ(per_feature_suffix(named, "meanabs"), "");
}
