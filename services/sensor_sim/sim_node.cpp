#include "sim_node.hpp"

#include "causal/dds/stop_timer.hpp"
#include "causal/config/exit_codes.hpp"
#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>

namespace causal::sim {

namespace {
std::string group_id(const std::string& prefix, int index) { return fmt::format("{}{:04d}", prefix, index); }
}  // namespace

SimNode::SimNode(SimOptions options)
    : options_(std::move(options)),
      participant_(dds::to_dds_settings(options_.dds, "sensor-sim")),
      frames_(participant_, dds::topics::kVibrationFrame, dds::profiles::kVibrationFrameWriter) {
  std::vector<std::string> names;
  for (int c = 1; c <= options_.channels; ++c) names.push_back("ch" + std::to_string(c));
  groups_.reserve(static_cast<std::size_t>(options_.groups));
  for (int i = 0; i < options_.groups; ++i) {
    const auto index = static_cast<std::uint64_t>(i);
    SvarModel model = make_group_model(options_.seed, index, options_.channels, options_.lag_order);
    dds::FrameHeader header;
    header.asset_group = group_id(options_.group_prefix, i);
    header.sample_rate_hz = options_.sample_rate_hz;
    header.channel_names = names;
    header.unit = "g";
    header.source = fmt::format("sensor-sim seed {}", options_.seed);
    if (i == 0) spdlog::info("{}: known factors {}", header.asset_group, describe_factors(model));
    spdlog::debug("{}: known factors {}", header.asset_group, describe_factors(model));
    groups_.push_back(Group{SvarGenerator(std::move(model), options_.seed, index), std::move(header), 0});
  }
}

void SimNode::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_all();
}

bool SimNode::sleep_until(Clock::time_point due) {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait_until(lock, std::min(due, deadline_), [this] { return stop_.load(); });
  return !stop_.load();
}

int SimNode::run() {
  started_ = Clock::now();
  // --max-runtime holds even inside a blocked write or the wait for readers: the timer raises the stop flag.
  dds::StopTimer runtime_limit(options_.max_runtime_s, [this] {
    spdlog::warn("max runtime {:.1f} s reached: stopping", options_.max_runtime_s);
    stop();
  });
  if (options_.max_runtime_s > 0) {
    deadline_ = started_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.max_runtime_s));
  }
  if (options_.wait_subscribers > 0) {
    spdlog::info("waiting up to {:.0f} s for {} reader(s) on domain {}", options_.wait_timeout_s,
                 options_.wait_subscribers, participant_.domain_id());
    const auto wait = std::chrono::milliseconds(static_cast<long>(options_.wait_timeout_s * 1000.0));
    if (!frames_.wait_for_readers(static_cast<std::size_t>(options_.wait_subscribers), wait, stop_)) {
      if (stop_.load()) {
        print_summary();
        return 0;
      }
      spdlog::error("no reader matched within {:.0f} s: is causal-estimator running on domain {} with the same "
                    "transport profile?",
                    options_.wait_timeout_s, participant_.domain_id());
      print_summary();
      return config::kExitNoPeer;
    }
  }
  spdlog::info("publishing {} asset group(s) {}..{}, {} channels, {} samples per frame, {}, {}",
               options_.groups, groups_.front().header.asset_group, groups_.back().header.asset_group,
               options_.channels, options_.frame_samples,
               options_.frames_per_group > 0 ? fmt::format("{} frames per group", options_.frames_per_group)
                                             : std::string("no frame bound"),
               options_.rate_hz > 0 ? fmt::format("{} samples/s per group", options_.rate_hz)
                                    : std::string("as fast as possible"));
  const auto origin = Clock::now();
  origin_ = origin;
  if (options_.wall_clock_stamps) {
    options_.start_time_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                 std::chrono::system_clock::now().time_since_epoch()).count();
  }
  Eigen::MatrixXd block;
  for (std::uint64_t round = 0; options_.frames_per_group == 0 || round < options_.frames_per_group; ++round) {
    if (options_.rate_hz > 0) {
      // Round r holds samples [r F, (r + 1) F): it is due once they have been "measured".
      const double due_s = static_cast<double>(round) * options_.frame_samples / options_.rate_hz;
      if (!sleep_until(origin + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(due_s)))) break;
    }
    if (!publish_round(round, block)) break;
  }
  // Nothing is lost on a normal exit: wait (bounded) until every reader has acknowledged every frame. After a
  // stop the readers may be gone too: wait briefly; never past --max-runtime.
  auto ack_wait = std::chrono::duration_cast<Clock::duration>(stop_.load() ? std::chrono::seconds(2) : std::chrono::seconds(30));
  if (deadline_ != Clock::time_point::max()) ack_wait = std::min(ack_wait, std::max(Clock::duration::zero(), deadline_ - Clock::now()));
  if (!frames_.wait_for_acknowledgments(std::chrono::duration_cast<std::chrono::milliseconds>(ack_wait))) {
    spdlog::warn("not every frame was acknowledged by the readers within {:.1f} s",
                 std::chrono::duration<double>(ack_wait).count());
  }
  spdlog::info("{} frames published in {:.2f} s{}", sent_, std::chrono::duration<double>(Clock::now() - started_).count(),
               stop_.load() ? " (stopped early)" : "");
  print_summary();
  return lost_ > 0 ? config::kExitLostOrRefused : config::kExitOk;
}

bool SimNode::publish_round(std::uint64_t round, Eigen::MatrixXd& block) {
  const auto rows = static_cast<Eigen::Index>(options_.frame_samples);
  const double ns_per_sample = 1e9 / options_.sample_rate_hz;
  const auto write_timeout = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.write_timeout_s));
  const bool stagger = options_.stagger && options_.rate_hz > 0;
  for (std::size_t gi = 0; gi < groups_.size(); ++gi) {
    auto& g = groups_[gi];
    if (stop_.load()) return false;
    // Staggered: group gi is due gi/K of a frame period after the round (and its samples are that much later).
    const double phase = stagger ? static_cast<double>(gi) / static_cast<double>(groups_.size()) : 0.0;
    if (stagger && gi > 0) {
      const double due_s = (static_cast<double>(round) + phase) * options_.frame_samples / options_.rate_hz;
      if (!sleep_until(origin_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(due_s)))) {
        return false;
      }
    }
    g.generator.next(rows, block);
    auto& h = g.header;
    h.discontinuity = (round == 0);  // each group's stream starts here: no lag may reach before it
    h.first_sample_time_ns =
        options_.start_time_ns +
        static_cast<std::int64_t>((static_cast<double>(h.first_sample_index) + phase * options_.frame_samples) *
                                  ns_per_sample);
    dds::to_frame(h, block, 0, rows, frame_);
    const auto deadline = std::min(Clock::now() + write_timeout, deadline_);
    const auto result = frames_.write_until(frame_, stop_, deadline);
    if (result == dds::WriteResult::Stopped) return false;
    if (result != dds::WriteResult::Ok) {
      if (Clock::now() >= deadline_) return false;  // the runtime bound, not the readers, ended this write
      ++lost_;
      spdlog::error("{}: frame {} lost: {}", h.asset_group, h.sequence,
                    result == dds::WriteResult::TimedOut
                        ? fmt::format("not accepted within {:.1f} s (readers stopped acknowledging)", options_.write_timeout_s)
                        : fmt::format("DDS write error, return code {}", frames_.last_error()));
    } else {
      ++g.sent;
      ++sent_;
    }
    // A lost frame still consumes its sequence number and samples: the reader sees the gap.
    ++h.sequence;
    h.first_sample_index += static_cast<std::uint64_t>(rows);
  }
  return true;
}

void SimNode::print_summary() const {
  std::uint64_t per_group = groups_.empty() ? 0 : groups_.front().sent;
  for (const auto& g : groups_) per_group = std::min(per_group, g.sent);
  // Machine-readable, on stdout, outside the log pattern; per_group = frames every group received.
  std::printf("sensor-sim: sent frames=%llu groups=%zu per_group=%llu lost=%llu\n",
              static_cast<unsigned long long>(sent_), groups_.size(), static_cast<unsigned long long>(per_group),
              static_cast<unsigned long long>(lost_));
  std::fflush(stdout);
}

}  // namespace causal::sim
