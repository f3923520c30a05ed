// Shards that divide the work: sensor-sim publishes 48 asset groups; several causal-estimator
// shards, each with content-filtered readers, must each RECEIVE exactly their own groups' frames (nothing of
// the others reaches them: foreign=0), together cover every group exactly once, deliver every factor message,
// and exit by themselves when the source has gone (--idle-exit), also a shard that owns no group at all.
//
// Exact expectations come from the set-up: which group belongs to which shard is computed here from the
// patterns written into the test's own shards file, or from FNV-1a as published (test vectors checked below),
// not from the code under test; frames = groups x frames per group, factor messages = frames x G (the
// parameter file tests/fault/estimator_fault.yaml: sample level, filter only, one report per 1024-sample frame).
// Fixed DDS domains 86 (shards file) and 87 (hash slices): the shards helper's range.
#include "loopback_settings.hpp"
#include "process_expect.hpp"
#include "process_runner.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
using causal::test::expect_exit_zero;
using causal::test::ServiceProcess;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kGroups = 48;
constexpr int kChannels = 4;
constexpr int kFramesPerGroup = 6;

std::string group_id(int i) {
  char id[16];
  std::snprintf(id, sizeof id, "sim-%04d", i);
  return id;
}

// FNV-1a 64 as published (offset basis 14695981039346656037, prime 1099511628211), written out here so the
// test does not take the shard of a group from the code it checks.
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 14695981039346656037ULL;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ULL;
  return h;
}

// Counts the factor batches (CausalFactorBatch: one per group, estimator, time scale and index) on the domain.
class FactorCounter {
 public:
  explicit FactorCounter(int domain)
      : participant_(settings(domain)),
        factors_(participant_, causal::dds::topics::kCausalFactors, causal::dds::profiles::kCausalFactorsReader) {
    loop_.attach(factors_.get());
    thread_ = std::thread([this] {
      while (loop_.wait(std::chrono::milliseconds(100))) count_ += factors_.take_all([](const auto&, const auto&) {});
    });
  }
  ~FactorCounter() {
    loop_.stop();
    thread_.join();
  }
  std::size_t count() const { return count_.load(); }

 private:
  static causal::dds::DdsSettings settings(int domain) {
    return causal::test::loopback_settings(domain, "fault-test-counter");
  }
  causal::dds::Participant participant_;
  causal::dds::TypedReader<causal_twin::CausalFactorBatchPubSubType> factors_;
  causal::dds::EventLoop loop_;
  std::thread thread_;
  std::atomic<std::size_t> count_{0};
};

struct ShardReport {
  int exit_code = -1;
  std::set<std::string> groups;  // from "asset 'sim-NNNN': F frames (0 lost, 0 refused)"
  std::uint64_t frames_received = 0, foreign = 0, published = 0;
  bool summary_found = false;
};

ShardReport report_of(ServiceProcess& p, std::optional<int> code) {
  ShardReport r;
  r.exit_code = code.value_or(-1);
  const std::string out = p.output();
  static const std::regex group_re("asset '(sim-\\d{4})': " + std::to_string(kFramesPerGroup) +
                                   " frames \\(0 lost, 0 refused\\)");
  for (auto it = std::sregex_iterator(out.begin(), out.end(), group_re); it != std::sregex_iterator(); ++it) {
    r.groups.insert((*it)[1]);
  }
  std::smatch m;
  static const std::regex frames_re(R"(summary topic=causal_twin/vibration_frame received=(\d+) lost=0 refused=0)");
  if (std::regex_search(out, m, frames_re)) r.frames_received = std::stoull(m[1]);
  static const std::regex shard_re(R"(summary shard=\S+ groups=\d+ foreign=(\d+))");
  if (std::regex_search(out, m, shard_re)) {
    r.summary_found = true;
    r.foreign = std::stoull(m[1]);
  }
  static const std::regex published_re(R"(published factors=(\d+) unpublished=0)");
  if (std::regex_search(out, m, published_re)) r.published = std::stoull(m[1]);
  return r;
}

fs::path work_dir(const std::string& name) { return causal::test::fresh_work_dir("causal_fault_shards", name); }

// Runs sensor-sim with the estimators given (extra arguments per shard) and checks the division exactly
// against `expected` (shard index -> the groups it must own; a shard may own none).
void run_and_check(int domain, const std::vector<std::vector<std::string>>& shard_args,
                   const std::vector<std::set<std::string>>& expected, const fs::path& work) {
  const std::string d = std::to_string(domain);
  FactorCounter counter(domain);
  std::vector<std::unique_ptr<ServiceProcess>> shards;
  for (std::size_t i = 0; i < shard_args.size(); ++i) {
    std::vector<std::string> argv = {CAUSAL_ESTIMATOR_BIN, "--domain", d, "--params", FAULT_ESTIMATOR_PARAMS,
                                     "--wait-for", "fault-test-counter", "--idle-exit", "2", "--max-runtime", "90"};
    argv.insert(argv.end(), shard_args[i].begin(), shard_args[i].end());
    shards.push_back(std::make_unique<ServiceProcess>("causal-estimator", argv,
                                                      (work / ("shard" + std::to_string(i) + ".log")).string()));
  }
  ServiceProcess sim("sensor-sim",
                     {SENSOR_SIM_BIN, "--domain", d, "--groups", std::to_string(kGroups), "--channels",
                      std::to_string(kChannels), "--frames-per-group", std::to_string(kFramesPerGroup), "--seed",
                      "7", "--wait-subscribers", std::to_string(shard_args.size()), "--wait-timeout", "30",
                      "--max-runtime", "60"},
                     (work / "sim.log").string());
  ASSERT_NO_FATAL_FAILURE(expect_exit_zero(sim, std::chrono::seconds(70)));
  const std::string sent = "sensor-sim: sent frames=" + std::to_string(kGroups * kFramesPerGroup) +
                           " groups=" + std::to_string(kGroups) + " per_group=" + std::to_string(kFramesPerGroup) +
                           " lost=0";
  EXPECT_NE(sim.output().find(sent), std::string::npos) << sim.output();

  // Every shard ends by itself (idle exit), the one with no group too.
  std::set<std::string> all;
  std::uint64_t published = 0;
  for (std::size_t i = 0; i < shards.size(); ++i) {
    const auto code = shards[i]->wait(std::chrono::seconds(30));
    ASSERT_TRUE(code.has_value()) << "shard " << i << " did not exit when idle:\n" << shards[i]->output();
    const ShardReport r = report_of(*shards[i], code);
    EXPECT_EQ(r.exit_code, 0) << shards[i]->output();
    EXPECT_TRUE(r.summary_found) << shards[i]->output();
    EXPECT_EQ(r.groups, expected[i]) << "shard " << i;
    // Received only its own groups' frames: the others' never reached its reader.
    EXPECT_EQ(r.frames_received, expected[i].size() * kFramesPerGroup) << "shard " << i;
    EXPECT_EQ(r.foreign, 0u) << "shard " << i << " received other shards' frames";
    // One factor batch (every outcome) per frame and group.
    EXPECT_EQ(r.published, expected[i].size() * kFramesPerGroup) << "shard " << i;
    for (const auto& g : r.groups) EXPECT_TRUE(all.insert(g).second) << g << " processed by two shards";
    published += r.published;
  }
  EXPECT_EQ(all.size(), std::size_t{kGroups}) << "union of the shards' groups";
  // Every factor batch crossed the wire (allow the last ones a moment).
  const auto until = Clock::now() + std::chrono::seconds(10);
  while (counter.count() < published && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(counter.count(), published);
  EXPECT_EQ(published, std::uint64_t{kGroups} * kFramesPerGroup);
}

}  // namespace

TEST(ShardedAssetGroups, Fnv1aMatchesThePublishedTestVectors) {
  EXPECT_EQ(fnv1a(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(fnv1a("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(fnv1a("foobar"), 0x85944171f73967e8ULL);
}

// Shards from a configuration file: three shards own 20, 20 and 8 groups, a fourth owns none.
TEST(ShardedAssetGroups, ShardsFromAFileReceiveExactlyTheirGroups) {
  const fs::path work = work_dir("file");
  const std::string file = (work / "shards.yaml").string();
  std::ofstream(file) << "shards:\n  a: [\"sim-000*\", \"sim-001?\"]\n  b: [\"sim-002*\", \"sim-003*\"]\n"
                         "  c: [\"sim-004*\"]\n  idle: [\"pump-*\"]\n";
  std::vector<std::set<std::string>> expected(4);
  for (int i = 0; i < kGroups; ++i) expected[static_cast<std::size_t>(i < 20 ? 0 : i < 40 ? 1 : 2)].insert(group_id(i));
  std::vector<std::vector<std::string>> args;
  for (const char* name : {"a", "b", "c", "idle"}) args.push_back({"--shards", file, "--shard", name});
  run_and_check(86, args, expected, work);
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}

// Hash slices (--shard-index/--shard-count): the division FNV-1a gives, each group exactly once.
TEST(ShardedAssetGroups, HashSlicesReceiveExactlyTheirGroups) {
  constexpr int kShards = 3;
  const fs::path work = work_dir("hash");
  std::vector<std::set<std::string>> expected(kShards);
  for (int i = 0; i < kGroups; ++i) expected[fnv1a(group_id(i)) % kShards].insert(group_id(i));
  for (const auto& e : expected) ASSERT_FALSE(e.empty()) << "the set-up should give every shard a group";
  std::vector<std::vector<std::string>> args;
  for (int s = 0; s < kShards; ++s) args.push_back({"--shard-index", std::to_string(s), "--shard-count", std::to_string(kShards)});
  run_and_check(87, args, expected, work);
  if (!HasFailure()) fs::remove_all(work);
  causal::test::clean_stale_shared_memory();
}
