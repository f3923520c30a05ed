#include "sim_node.hpp"

#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>

namespace causal::sim {

namespace {
std::string group_id(const std::string& prefix, int index) { return fmt::format("{}{:04d}", prefix, index); }
}  // namespace

dds::SourceDriverOptions driver_options(const SimOptions& o, bool frames) {
  dds::SourceDriverOptions d;
  d.wait = o.wait;
  d.frames = frames;
  d.conditions = !frames;
  d.write_timeout_s = o.write_timeout_s;
  d.max_runtime_s = o.max_runtime_s;
  return d;
}

SvarFrames::SvarFrames(SimOptions& options) : options_(options) {
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

void SvarFrames::start(dds::SourceDriver& driver) {
  driver_ = &driver;
  spdlog::info("publishing {} asset group(s) {}..{}, {} channels, {} samples per frame, {}, {}",
               options_.groups, groups_.front().header.asset_group, groups_.back().header.asset_group,
               options_.channels, options_.frame_samples,
               options_.frames_per_group > 0 ? fmt::format("{} frames per group", options_.frames_per_group)
                                             : std::string("no frame bound"),
               options_.rate_hz > 0 ? fmt::format("{} samples/s per group", options_.rate_hz)
                                    : std::string("as fast as possible"));
  if (options_.wall_clock_stamps) {
    options_.start_time_ns = io::utc_now_ns();
  }
}

dds::Take SvarFrames::next(dds::SourceDriver& driver, dds::SourceBlock& out) {
  if (next_group_ == groups_.size()) {
    next_group_ = 0;
    ++round_;
  }
  if (driver.stopping() || (options_.frames_per_group > 0 && round_ >= options_.frames_per_group)) {
    return dds::Take::End;
  }
  const std::size_t gi = next_group_;
  const bool stagger = options_.stagger && options_.rate_hz > 0;
  // Staggered: group gi is due gi/K of a frame period after the round (and its samples are that much later).
  const double phase = stagger ? static_cast<double>(gi) / static_cast<double>(groups_.size()) : 0.0;
  if (options_.rate_hz > 0 && (gi == 0 || stagger)) {
    // Round r holds samples [r F, (r + 1) F): it is due once they have been "measured".
    const double due_s = (static_cast<double>(round_) + phase) * options_.frame_samples / options_.rate_hz;
    if (!driver.pace(due_s)) return dds::Take::End;
  }
  auto& g = groups_[gi];
  const auto rows = static_cast<Eigen::Index>(options_.frame_samples);
  g.generator.next(rows, block_);
  out.kind = dds::SourceBlock::Kind::Frame;
  out.frame = g.header;
  out.frame.discontinuity = (round_ == 0);  // each group's stream starts here: no lag may reach before it
  // Sample times from the sample index (round r starts at sample r F), never from the clock.
  const double first_sample = static_cast<double>(round_ * static_cast<std::uint64_t>(rows));
  out.frame.first_sample_time_ns =
      options_.start_time_ns +
      static_cast<std::int64_t>((first_sample + phase * options_.frame_samples) * (1e9 / options_.sample_rate_hz));
  out.samples = &block_;
  out.first_row = 0;
  out.rows = rows;
  ++next_group_;
  return dds::Take::Block;
}

void SvarFrames::written(const dds::SourceBlock&, dds::WriteResult result, const causal_twin::VibrationFrame*) {
  if (result == dds::WriteResult::Ok) ++groups_[next_group_ - 1].sent;
}

void SvarFrames::summary(const dds::SourceCounts& counts, bool stopped) const {
  if (driver_) {
    spdlog::info("{} frames published in {:.2f} s{}", counts.frames, driver_->elapsed_s(),
                 stopped ? " (stopped early)" : "");
  }
  std::uint64_t per_group = groups_.empty() ? 0 : groups_.front().sent;
  for (const auto& g : groups_) per_group = std::min(per_group, g.sent);
  // Machine-readable, on stdout, outside the log pattern; per_group = frames every group received.
  std::printf("sensor-sim: sent frames=%llu groups=%zu per_group=%llu lost=%llu\n",
              static_cast<unsigned long long>(counts.frames), groups_.size(),
              static_cast<unsigned long long>(per_group), static_cast<unsigned long long>(counts.lost));
  std::fflush(stdout);
}

SimNode::SimNode(SimOptions options)
    : options_(std::move(options)),
      participant_(dds::to_dds_settings(options_.dds, "sensor-sim")),
      driver_(participant_, driver_options(options_, true)),
      source_(options_) {}

}  // namespace causal::sim
