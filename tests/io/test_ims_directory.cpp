#include "causal/io/ims_directory.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "causal/io/input_error.hpp"
#include "causal/io/time_format.hpp"
#include "io_test_util.hpp"

using causal::io::InputError;
using causal::io::list_ims_directory;
using causal::io::parse_ims_timestamp;
using causal::io::test::TempDir;

namespace {
constexpr std::int64_t kSec = 1'000'000'000;
constexpr std::int64_t kRunStart = 1076581959LL * kSec;  // 2004-02-12 10:32:39 UTC (calendar.timegm)
}  // namespace

TEST(ImsTimestamp, ParsesRunStartAndIndex492) {
  EXPECT_EQ(parse_ims_timestamp("2004.02.12.10.32.39"), kRunStart);
  // README: index i is the start + 10 i minutes; index 492 is 2004.02.15.20.32.39.
  EXPECT_EQ(parse_ims_timestamp("2004.02.15.20.32.39"), kRunStart + 4920LL * 60 * kSec);
  EXPECT_EQ(parse_ims_timestamp("2004.02.17.07.12.39"), kRunStart + 7000LL * 60 * kSec);  // index 700
  EXPECT_EQ(causal::io::format_utc(*parse_ims_timestamp("2004.02.15.20.32.39")), "2004-02-15 20:32:39");
}

TEST(ImsTimestamp, AcceptsGzAndDirectory) {
  EXPECT_EQ(parse_ims_timestamp("2004.02.12.10.32.39.gz"), kRunStart);
  EXPECT_EQ(parse_ims_timestamp("/some/dir/2004.02.12.10.32.39"), kRunStart);
  EXPECT_EQ(parse_ims_timestamp("dir/2004.02.12.10.32.39.gz"), kRunStart);
}

TEST(ImsTimestamp, RejectsOtherNames) {
  for (const char* bad : {"README.md", "merged_dataset_BearingTest_2.csv", "2004.02.12.10.32.39.txt",
                          "2004.02.12.10.32.39.gz.bak", "2004-02-12 10:32:39", "2004.02.12.10.32", ".gz",
                          "2004.02.30.10.32.39", "2004.02.12.25.32.39", "x2004.02.12.10.32.39",
                          "2004.02.12.10.32.390", ""}) {
    EXPECT_FALSE(parse_ims_timestamp(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(ImsDirectory, SortsByTimeAndIgnoresOthers) {
  TempDir dir;
  // Written out of order, mixed plain/gz, plus non-snapshot entries.
  dir.write("2004.02.12.10.52.39", "0 0 0 0\n");
  dir.write_gz("2004.02.12.10.42.39.gz", "0 0 0 0\n");
  dir.write("2004.02.12.10.32.39", "0 0 0 0\n");
  dir.write("2004.02.13.00.02.39", "0 0 0 0\n");  // crosses a day: checks numeric, not only lexical order
  dir.write("README.md", "hello\n");
  dir.write("stats.csv", "a,b\n");
  std::filesystem::create_directory(dir.file("2004.02.12.11.02.39"));  // a folder with a snapshot name

  const auto listing = list_ims_directory(dir.path());
  ASSERT_EQ(listing.snapshots.size(), 4u);
  const char* expect_names[] = {"2004.02.12.10.32.39", "2004.02.12.10.42.39.gz", "2004.02.12.10.52.39",
                                "2004.02.13.00.02.39"};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(listing.snapshots[i].name, expect_names[i]);
    EXPECT_EQ(listing.snapshots[i].index, i);
    EXPECT_EQ(listing.snapshots[i].path, dir.file(expect_names[i]));
    EXPECT_EQ(listing.snapshots[i].time_ns, *parse_ims_timestamp(expect_names[i]));
  }
  EXPECT_EQ(listing.snapshots[1].time_ns - listing.snapshots[0].time_ns, 600 * kSec);
  const std::vector<std::string> expect_ignored = {"2004.02.12.11.02.39", "README.md", "stats.csv"};
  EXPECT_EQ(listing.ignored, expect_ignored);
}

TEST(ImsDirectory, DuplicateTimeKeepsPlainFile) {
  TempDir dir;
  dir.write("2004.02.12.10.32.39", "1 2\n");
  dir.write_gz("2004.02.12.10.32.39.gz", "1 2\n");
  const auto listing = list_ims_directory(dir.path());
  ASSERT_EQ(listing.snapshots.size(), 1u);
  EXPECT_EQ(listing.snapshots[0].name, "2004.02.12.10.32.39");
  EXPECT_EQ(listing.ignored, std::vector<std::string>{"2004.02.12.10.32.39.gz"});
}

TEST(ImsDirectory, MissingDirThrowsNamingIt) {
  TempDir dir;
  const std::string missing = dir.file("does_not_exist");
  try {
    list_ims_directory(missing);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), missing);
    EXPECT_EQ(e.line(), 0u);
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos);
  }
}

TEST(ImsDirectory, NotADirectoryOrNoSnapshotThrows) {
  TempDir dir;
  const std::string file = dir.write("plain.txt", "x\n");
  EXPECT_THROW(list_ims_directory(file), InputError);
  dir.write("README.md", "only docs\n");
  try {
    list_ims_directory(dir.path());
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no IMS snapshot"), std::string::npos) << e.what();
  }
}

TEST(ImsDirectory, SharedRawFolderIfPresent) {
  if (!causal::io::test::shared_available()) {
    GTEST_SKIP() << "full IMS data not found at " << causal::io::test::shared_ims2()
                 << " (set -DCAUSAL_TWIN_SHARED_DIR=<shared folder>)";
  }
  const auto listing = list_ims_directory(causal::io::test::shared_ims2() + "/raw");
  // README: raw/ keeps 321 of the 984 files; indices 0,4,...,880 then 884..983.
  ASSERT_EQ(listing.snapshots.size(), 321u);
  EXPECT_EQ(listing.snapshots.front().name, "2004.02.12.10.32.39");
  EXPECT_EQ(listing.snapshots.back().name, "2004.02.19.06.22.39");
  EXPECT_EQ(listing.snapshots[1].time_ns - listing.snapshots[0].time_ns, 40LL * 60 * kSec);
  for (std::size_t i = 1; i < listing.snapshots.size(); ++i) {
    ASSERT_GT(listing.snapshots[i].time_ns, listing.snapshots[i - 1].time_ns);
  }
  // Run index = minutes since start / 10; the last is 983.
  EXPECT_EQ((listing.snapshots.back().time_ns - kRunStart) / (600 * kSec), 983);
}
