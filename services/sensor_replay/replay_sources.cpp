#include "replay_sources.hpp"

#include "causal/dds/source_driver.hpp"
#include "causal/io/input_error.hpp"
#include "causal/io/name_limits.hpp"
#include "causal/io/time_format.hpp"
#include "causal/io/time_gaps.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace causal::replay {

namespace {

// "6.0 days", "5.6 h", "10 min": a duration for the log.
std::string duration_text(std::int64_t ns) {
  const double s = static_cast<double>(ns) * 1e-9;
  if (s >= 2 * 86400.0) return fmt::format("{:.1f} days", s / 86400.0);
  if (s >= 2 * 3600.0) return fmt::format("{:.1f} h", s / 3600.0);
  if (s >= 120.0) return fmt::format("{:.0f} min", s / 60.0);
  return fmt::format("{:.3g} s", s);
}

// Channel names from the source file meet the one name limit (causal/io/name_limits.hpp) here, where they enter,
// not at every reader of the frames (which would refuse them all). Throws io::InputError naming the first.
void check_names(const std::string& path, const std::vector<std::string>& channel_names) {
  for (const auto& name : channel_names) {
    if (const char* problem = io::name_problem(name)) {
      throw io::InputError(path, 0,
                           "channel name '" + name.substr(0, 40) + (name.size() > 40 ? "..." : "") + "' is " + problem +
                               " (names are 1 to " + std::to_string(io::kMaxNameBytes) + " bytes)");
    }
  }
}

// The first snapshot to send again for a restarted estimator of `group`, or nullopt (nothing to resend).
std::optional<std::size_t> rewind_point(const dds::PublishedSnapshots& published, const std::string& group,
                                        std::size_t first, std::size_t next, const std::vector<std::string>& who) {
  const auto it = published.find(group);
  const std::size_t resume =
      it != published.end() ? std::max<std::size_t>(first, static_cast<std::size_t>(it->second + 1)) : first;
  if (resume >= next) return std::nullopt;
  spdlog::warn("a new {} appeared (a restart?): resending from snapshot {} (the last one published for '{}' was {})",
               fmt::join(who, "/"), resume, group, it != published.end() ? std::to_string(it->second) : "none");
  return resume;
}

}  // namespace

void ReplaySource::select(std::size_t available) {
  first_ = std::min(options_.first_snapshot, available);
  last_ = available;
  if (options_.max_snapshots > 0) last_ = std::min(last_, first_ + options_.max_snapshots);
  next_ = first_;
}

bool ReplaySource::rewound(dds::SourceDriver& driver) {
  const auto published = driver.restarted();
  if (!published) return false;
  const auto resume = rewind_point(*published, options_.asset_group, first_, next_, options_.wait.wait_for);
  if (!resume) return false;
  ++rewinds_;
  next_ = *resume;
  return true;
}

bool ReplaySource::pace(dds::SourceDriver& driver, std::int64_t plant_ns) {
  if (!plant_origin_ns_) plant_origin_ns_ = plant_ns;
  const double due_s = options_.speed > 0.0 ? static_cast<double>(plant_ns - *plant_origin_ns_) * 1e-9 / options_.speed : 0.0;
  return driver.pace(due_s);
}

void ReplaySource::report_progress(std::size_t done, bool force) const {
  const auto now = std::chrono::steady_clock::now();
  if (!force && std::chrono::duration<double>(now - last_progress_).count() < options_.progress_every_s) return;
  last_progress_ = now;
  const std::size_t total = last_ - first_;
  const double elapsed = driver_->elapsed_s();
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
  spdlog::info("progress: {}/{} snapshots, {:.1f} snapshots/s, ETA {:.0f} s", done, total, rate, eta);
}

void SnapshotReplay::start(dds::SourceDriver& driver) {
  driver_ = &driver;
  source_ = options_.source == SourceKind::ImsDirectory
                ? open_ims_directory(options_.path, options_.channels, options_.channel_names)
                : open_channel_csv(options_.path, options_.channels, options_.channel_names);
  check_names(options_.path, source_->channel_names());
  select(source_->size());
  spdlog::info("replaying {} snapshot(s) of {} from {} as asset group '{}', channels [{}], {} samples per frame, "
               "speed {}",
               last_ - first_, source_->size(), options_.path, options_.asset_group,
               fmt::join(source_->channel_names(), ", "), options_.frame_samples,
               options_.speed > 0 ? fmt::format("x{}", options_.speed) : "as fast as possible");
  header_.asset_group = options_.asset_group;
  header_.sample_rate_hz = options_.sample_rate_hz;
  header_.channel_names = source_->channel_names();
  header_.unit = options_.unit;
}

dds::Take SnapshotReplay::next(dds::SourceDriver& driver, dds::SourceBlock& out) {
  while (!driver.stopping()) {
    if (!loaded_) {
      if (next_ >= last_) return dds::Take::End;
      // Frames sent again keep their sample indices.
      if (rewound(driver)) driver.renumber_from(options_.asset_group, next_);
      snapshot_ = source_->load(next_);
      row_ = 0;
      loaded_ = true;
    }
    const Eigen::Index n = snapshot_.samples.rows();
    if (row_ >= n) {  // the snapshot is out
      ++snapshots_sent_;
      spdlog::debug("snapshot {} ({}) published", snapshot_.name, io::format_utc(snapshot_.time_ns));
      report_progress(next_ + 1 - first_, false);
      ++next_;
      loaded_ = false;
      continue;
    }
    const Eigen::Index rows = std::min<Eigen::Index>(options_.frame_samples, n - row_);
    header_.source = snapshot_.name;
    header_.snapshot_index = next_;
    header_.first_sample_time_ns =
        snapshot_.time_ns + static_cast<std::int64_t>(static_cast<double>(row_) * (1e9 / options_.sample_rate_hz));
    header_.discontinuity = (row_ == 0);  // every snapshot starts a new contiguous segment
    header_.end_of_segment = (row_ + rows == n);
    if (!pace(driver, header_.first_sample_time_ns)) return dds::Take::End;
    out.kind = dds::SourceBlock::Kind::Frame;
    out.frame = header_;
    out.samples = &snapshot_.samples;
    out.first_row = row_;
    out.rows = rows;
    row_ += rows;
    return dds::Take::Block;
  }
  return dds::Take::End;
}

void SnapshotReplay::written(const dds::SourceBlock& block, dds::WriteResult result, const causal_twin::VibrationFrame*) {
  if (result == dds::WriteResult::Ok) samples_sent_ += static_cast<std::uint64_t>(block.rows);
}

void SnapshotReplay::summary(const dds::SourceCounts& counts, bool stopped) const {
  if (!driver_) return;  // never started (no readers)
  report_progress(last_ - first_, true);
  spdlog::info("published {} frames ({} samples per channel) in {:.2f} s{}", counts.frames, samples_sent_,
               driver_->elapsed_s(), stopped ? " (stopped early)" : "");
  spdlog::info("summary topic=causal_twin/vibration_frame sent={} snapshots={} rewinds={}", counts.frames,
               snapshots_sent_, rewinds_);
}

void FeatureTableReplay::start(dds::SourceDriver& driver) {
  driver_ = &driver;
  io::FeatureTable table = io::read_feature_table(options_.path, options_.feature_suffix);
  if (options_.feature_suffix.empty()) {
    // A table as it is: one column per channel, or <channel>_<feature> columns of several features.
    if (const std::string suffix = io::per_feature_suffix(table, options_.feature_name); !suffix.empty()) {
      table = io::read_feature_table(options_.path, suffix);
      spdlog::info("{}: one column per channel and feature: publishing the '{}' columns", options_.path, suffix);
    }
  }
  // Time gaps over the whole table (a --first-snapshot subset keeps the recording's cadence and its gaps).
  const io::TimeGaps gaps = io::find_time_gaps(table.time_ns, options_.gap_factor);
  after_gap_.assign(table.time_ns.size(), false);
  for (const std::size_t r : gaps.rows) {
    after_gap_[r] = true;
    spdlog::info("time gap of {} before snapshot {} ({} after {}; usual interval {}, gaps are > {} x that): published "
                 "as a discontinuity",
                 duration_text(table.time_ns[r] - table.time_ns[r - 1]), r, io::format_utc(table.time_ns[r]),
                 io::format_utc(table.time_ns[r - 1]), duration_text(gaps.median_interval_ns), options_.gap_factor);
  }
  time_gaps_ = gaps.rows.size();
  values_ = select_channels(table.values, options_.channels);
  time_ns_ = std::move(table.time_ns);
  header_.asset_group = options_.asset_group;
  header_.feature = options_.feature_name;
  header_.channel_names = select_names(table.channel_names, options_.channels, options_.channel_names);
  check_names(options_.path, header_.channel_names);
  const auto rows = static_cast<std::size_t>(values_.rows());
  select(rows);
  spdlog::info("replaying {} condition vector(s) of {} ('{}') from {} as asset group '{}'", last_ - first_, rows,
               header_.feature, options_.path, options_.asset_group);
}

dds::Take FeatureTableReplay::next(dds::SourceDriver& driver, dds::SourceBlock& out) {
  if (driver.stopping() || next_ >= last_) return dds::Take::End;
  rewound(driver);  // condition vectors are numbered by their snapshot index: nothing to renumber
  const std::size_t i = next_++;
  header_.snapshot_index = i;
  header_.time_ns = time_ns_[i];
  header_.discontinuity = (i == first_) || after_gap_[i];
  if (!pace(driver, header_.time_ns)) return dds::Take::End;
  out.kind = dds::SourceBlock::Kind::Condition;
  out.condition = header_;
  out.values = values_.row(static_cast<Eigen::Index>(i)).transpose();
  return dds::Take::Block;
}

void FeatureTableReplay::written(const dds::SourceBlock&, dds::WriteResult result, const causal_twin::VibrationFrame*) {
  if (result != dds::WriteResult::Ok) return;
  ++sent_;
  report_progress(sent_, false);
}

void FeatureTableReplay::summary(const dds::SourceCounts& counts, bool stopped) const {
  if (!driver_) return;  // never started (no readers)
  report_progress(sent_, true);
  spdlog::info("published {} condition vectors in {:.2f} s{}", counts.conditions, driver_->elapsed_s(),
               stopped ? " (stopped early)" : "");
  spdlog::info("summary topic=causal_twin/condition_input sent={} rewinds={} time_gaps={}", counts.conditions, rewinds_,
               time_gaps_);
}

}  // namespace causal::replay
