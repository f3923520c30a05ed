// Delivery contract, same input, same output: the 984-row feature replay of IMS test 2 run 5 times through
// deploy/launch.sh --record (all services, as fast as possible). Nothing lost and nothing duplicated means
// the recordings cannot differ: the condition vectors, the condition-level filter factors, the alarms and the
// recommendations must be byte-identical to the first run's. A difference names the file and the first line.
#include "delivery_checks.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace fs = std::filesystem;
using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kRuns = 5;
constexpr std::uint64_t kSnapshots = 984;  // rows of the feature table
const std::vector<std::string> kCompared = {"conditions_ims2-shaft1_meanabs.csv",
                                            "factors_ims2-shaft1_condition_filter.csv", "alarms.csv",
                                            "recommendations.csv", "prognosis.csv"};

// "line N differs" (1-based) or "" when equal.
std::string first_difference(const std::string& a, const std::string& b) {
  if (a == b) return {};
  std::size_t line = 1;
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (a[i] != b[i]) return "line " + std::to_string(line) + " differs";
    if (a[i] == '\n') ++line;
  }
  return "one is a prefix of the other, from line " + std::to_string(line) + " (sizes " + std::to_string(a.size()) +
         " and " + std::to_string(b.size()) + ")";
}

std::vector<std::string> sorted_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::sort(lines.begin(), lines.end());
  return lines;
}

}  // namespace

TEST(RepeatableRecording, FiveFeatureReplaysRecordByteIdenticalFiles) {
  const fs::path work = work_dir("repeat");
  const std::string table = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
  // launch.sh finds the services under $CAUSAL_TWIN_BUILD_DIR/services; the children inherit it.
  ASSERT_EQ(::setenv("CAUSAL_TWIN_BUILD_DIR", CAUSAL_TWIN_BUILD_DIR, 1), 0);

  std::map<std::string, std::string> reference;  // run 1's bytes per file
  for (int run = 1; run <= kRuns; ++run) {
    const fs::path out = work / ("run" + std::to_string(run));
    const fs::path logs = work / ("logs" + std::to_string(run));
    const std::string d = std::to_string(delivery_domain_id(4)  /* the runs follow each other */);
    const auto started = Clock::now();
    ServiceProcess launch("launch.sh",
                          {std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/launch.sh", "--domain", d, "--features", table,
                           "--feature-suffix", "_meanabs", "--feature-name", "meanabs", "--speed", "0", "--record",
                           out.string(), "--logs", logs.string(), "--max-runtime", "120"},
                          (work / ("launch" + std::to_string(run) + ".log")).string());
    const auto code = launch.wait(std::chrono::seconds(150));
    const double wall = std::chrono::duration<double>(Clock::now() - started).count();
    ASSERT_TRUE(code.has_value()) << "run " << run << " did not finish in 150 s:\n" << launch.output();
    ASSERT_EQ(*code, 0) << "run " << run << ": a service lost, dropped or refused data:\n" << launch.output();

    std::printf("[ delivery ] run %d (domain %s, %.1f s):", run, d.c_str(), wall);
    for (const auto& name : kCompared) {
      const RecordedFile f = read_recorded(out / name);
      ASSERT_TRUE(f.exists) << "run " << run << ": " << name << " not recorded\n" << launch.output();
      std::printf(" %s %llu rows %llu bytes;", name.c_str(), static_cast<unsigned long long>(f.rows),
                  static_cast<unsigned long long>(f.bytes));
      EXPECT_TRUE(f.repeated.empty()) << "run " << run << ": " << name << " has a row twice";
      const std::string bytes = read_text(out / name);
      if (run == 1) {
        reference[name] = bytes;
      } else {
        EXPECT_EQ(first_difference(reference[name], bytes), "")
            << "run " << run << " vs run 1: " << name
            << (sorted_lines(reference[name]) == sorted_lines(bytes) ? ": the same rows in another order"
                                                                     : ": different rows");
      }
    }
    std::printf("\n");
    // Run 1 alone is checked against the input: one condition row and one factor row per snapshot.
    if (run == 1) {
      EXPECT_EQ(read_recorded(out / kCompared[0]).indices.size(), kSnapshots);
      EXPECT_EQ(read_recorded(out / kCompared[1]).indices.size(), kSnapshots);
    }
  }
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
