// The one source driver (causal/dds/source_driver.hpp) with a real DDS reader in this process on a private
// loopback domain: a source that is one class gets its frames numbered per asset group (gap-free sequence and
// sample indices), a snapshot sent again after renumber_from keeps its sample indices, every frame arrives
// exactly once with its samples, and the exit codes say no reader (3) and refused input (4).
#include "causal/config/exit_codes.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/source_driver.hpp"
#include "causal/dds/topics.hpp"
#include "loopback_settings.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <map>
#include <thread>
#include <string>
#include <vector>

namespace {

using causal::dds::SourceBlock;
using causal::dds::Take;
constexpr Eigen::Index kRows = 16;

int domain(int salt) { return 150 + static_cast<int>((static_cast<unsigned>(::getpid()) * 7u + salt) % 80u); }

// Snapshots 0, 1 of groups a and b (two frames each), then snapshot 1 of group a again after renumber_from.
class TwoGroups final : public causal::dds::SampleSource {
 public:
  Take next(causal::dds::SourceDriver& driver, SourceBlock& out) override {
    if (step_ == 10) return Take::End;
    const int s = step_++;
    const bool again = s >= 8;
    const std::string group = again || s % 2 == 0 ? "a" : "b";
    const std::uint64_t snapshot = again ? 1 : static_cast<std::uint64_t>(s / 4);
    const int row = again ? s - 8 : (s / 2) % 2;  // frame within the snapshot
    if (again && row == 0) {
      EXPECT_TRUE(driver.renumber_from("a", 1));
    }
    samples_ = Eigen::MatrixXd::Constant(2 * kRows, 2, static_cast<double>(s));
    out.kind = SourceBlock::Kind::Frame;
    out.frame.asset_group = group;
    out.frame.sample_rate_hz = 1000.0;
    out.frame.channel_names = {"x", "y"};
    out.frame.unit = "V";
    out.frame.snapshot_index = snapshot;
    out.frame.first_sample_time_ns = 1'000'000'000LL * static_cast<std::int64_t>(snapshot + 1) + row * 16'000'000LL;
    out.frame.discontinuity = row == 0;
    out.frame.end_of_segment = row == 1;
    out.samples = &samples_;
    out.first_row = row * kRows;
    out.rows = kRows;
    return Take::Block;
  }
  std::uint64_t refused() const override { return refused_; }
  std::uint64_t refused_ = 0;

 private:
  int step_ = 0;
  Eigen::MatrixXd samples_;
};

// Frames, the first once the participant `peer` matched (waiting at most timeout_s).
causal::dds::SourceDriverOptions frames_after(const std::string& peer, double timeout_s) {
  causal::dds::SourceDriverOptions o;
  o.frames = true;
  o.wait.wait_for = {peer};
  o.wait.wait_timeout_s = timeout_s;
  return o;
}

struct Received {
  std::uint64_t sequence, first_sample_index;
  double first_value;
};

TEST(SourceDriver, NumbersFramesPerGroupAndRenumbersASnapshotSentAgain) {
  const int d = domain(1);
  causal::dds::Participant reader_side(causal::test::loopback_settings(d, "test-reader"));
  causal::dds::TypedReader<causal_twin::VibrationFramePubSubType> reader(
      reader_side, causal::dds::topics::kVibrationFrame, causal::dds::profiles::kVibrationFrameReader);
  causal::dds::Participant writer_side(causal::test::loopback_settings(d, "test-source"));
  causal::dds::SourceDriver driver(writer_side, frames_after("test-reader", 20.0));
  TwoGroups source;
  ASSERT_EQ(driver.run(source), causal::config::kExitOk);

  std::map<std::string, std::vector<Received>> got;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  std::size_t total = 0;
  while (total < 10 && std::chrono::steady_clock::now() < deadline) {
    total += reader.take_all([&](const causal_twin::VibrationFrame& f, const auto&) {
      got[f.asset_group()].push_back({f.sequence_number(), f.first_sample_index(), f.samples().front()});
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_EQ(total, 10u);
  ASSERT_EQ(got["a"].size(), 6u);
  ASSERT_EQ(got["b"].size(), 4u);
  // Group a: snapshots 0 and 1, then snapshot 1 again: the sequence goes on, the sample indices repeat.
  const std::vector<std::uint64_t> a_seq{0, 1, 2, 3, 4, 5}, a_first{0, 16, 32, 48, 32, 48};
  const std::vector<double> a_value{0, 2, 4, 6, 8, 9};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(got["a"][i].sequence, a_seq[i]) << i;
    EXPECT_EQ(got["a"][i].first_sample_index, a_first[i]) << i;
    EXPECT_EQ(got["a"][i].first_value, a_value[i]) << i;
  }
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(got["b"][i].sequence, i);
    EXPECT_EQ(got["b"][i].first_sample_index, 16 * i);
  }
}

TEST(SourceDriver, NoReaderInTimeIsExit3AndRefusedInputIsExit4) {
  const int d = domain(2);
  causal::dds::Participant writer_side(causal::test::loopback_settings(d, "test-source"));
  causal::dds::SourceDriverOptions o = frames_after("nobody", 0.5);
  {
    causal::dds::SourceDriver driver(writer_side, o);
    TwoGroups source;
    EXPECT_EQ(driver.run(source), causal::config::kExitNoPeer);
  }
  o.wait = {};
  o.wait.wait_subscribers = 0;  // publish without readers: nothing lost, but the source refused input
  causal::dds::SourceDriver driver(writer_side, o);
  TwoGroups source;
  source.refused_ = 1;
  EXPECT_EQ(driver.run(source), causal::config::kExitLostOrRefused);
}

}  // namespace
