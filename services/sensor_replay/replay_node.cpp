#include "replay_node.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/dds/peer_wait.hpp"

#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"
#include "causal/io/feature_table.hpp"
#include "causal/io/input_error.hpp"
#include "causal/io/name_limits.hpp"
#include "causal/io/time_format.hpp"
#include "causal/io/time_gaps.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace causal::replay {

namespace {
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// "6.0 days", "5.6 h", "10 min": a duration for the log.
std::string duration_text(std::int64_t ns) {
  const double s = static_cast<double>(ns) * 1e-9;
  if (s >= 2 * 86400.0) return fmt::format("{:.1f} days", s / 86400.0);
  if (s >= 2 * 3600.0) return fmt::format("{:.1f} h", s / 3600.0);
  if (s >= 120.0) return fmt::format("{:.0f} min", s / 60.0);
  return fmt::format("{:.3g} s", s);
}

}  // namespace

ReplayNode::ReplayNode(ReplayOptions options)
    : options_(std::move(options)), participant_(dds::to_dds_settings(options_.dds, "sensor-replay")) {
  if (options_.source == SourceKind::FeatureTable) {
    conditions_ = std::make_unique<dds::TypedWriter<causal_twin::ConditionVectorPubSubType>>(
        participant_, dds::topics::kConditionInput, dds::profiles::kConditionInputWriter);
  } else {
    frames_ = std::make_unique<dds::TypedWriter<causal_twin::VibrationFramePubSubType>>(
        participant_, dds::topics::kVibrationFrame, dds::profiles::kVibrationFrameWriter);
  }
  for (const auto& spec : options_.wait_for) wanted_.push_back(dds::parse_named_readers(spec));
  if (!wanted_.empty()) {
    progress_ = std::make_unique<dds::TypedReader<causal_twin::ConditionVectorPubSubType>>(
        participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorReader);
  }
}

template <typename Writer>
std::optional<std::size_t> ReplayNode::rewind_point(const Writer& writer, std::size_t first, std::size_t next) {
  if (!progress_) return std::nullopt;
  progress_->take_all([this](const causal_twin::ConditionVector& c, const auto&) {
    if (c.asset_group() == options_.asset_group && (!published_ || c.snapshot_index() > *published_)) {
      published_ = c.snapshot_index();
    }
  });
  bool appeared = false;
  for (const auto& w : wanted_) {
    for (const auto& guid : writer.readers_named(w.name)) appeared = known_readers_.insert(guid).second || appeared;
  }
  const bool first_look = !readers_known_;
  readers_known_ = true;
  if (!appeared || first_look) return std::nullopt;
  const std::size_t resume = published_ ? std::max<std::size_t>(first, static_cast<std::size_t>(*published_ + 1)) : first;
  if (resume >= next) return std::nullopt;
  ++rewinds_;
  spdlog::warn("a new {} appeared (a restart?): resending from snapshot {} (the last one published for '{}' was {})",
               fmt::join(options_.wait_for, "/"), resume, options_.asset_group,
               published_ ? std::to_string(*published_) : "none");
  return resume;
}

template <typename Writer>
bool ReplayNode::readers_present(const Writer& writer, bool first) {
  const std::size_t want = static_cast<std::size_t>(options_.wait_subscribers);
  // At the start every reader asked for must be there; later one of each name is enough (a hot-standby
  // estimator carries on alone), and none of a name means pause until it is back (a restart).
  bool missing = writer.matched_readers() < (first ? want : std::min<std::size_t>(want, 1));
  for (const auto& w : wanted_) missing = missing || writer.matched_readers_named(w.name) < (first ? w.count : 1);
  if (!missing) return true;
  const std::string what =
      fmt::format("{} reader(s){}{} on domain {}", want, wanted_.empty() ? "" : " including ",
                  fmt::join(options_.wait_for, ", "), participant_.domain_id());
  const std::string bound = options_.wait_timeout_s > 0 ? fmt::format("up to {:.0f} s", options_.wait_timeout_s)
                                                         : std::string("for as long as it takes");
  if (first) {
    spdlog::info("waiting {} for {}", bound, what);
  } else {
    spdlog::warn("a reader it waits for has gone ({}): pausing until it is back ({})",
                 fmt::join(options_.wait_for, ", "), bound);
  }
  std::vector<dds::NamedReaders> need = wanted_;
  if (!first) {
    for (auto& w : need) w.count = 1;
  }
  const auto ready = [&](std::chrono::milliseconds limit) {
    return writer.wait_for_readers(first ? want : std::min<std::size_t>(want, 1), limit, stop_) &&
           dds::wait_for_named_readers(writer, need, limit, stop_).empty();
  };
  const bool ok = dds::wait_for_peers(ready, options_.wait_timeout_s, stop_, what);
  if (!ok && !stop_.load()) {
    readers_missing_ = true;
    spdlog::error("the readers did not match within {:.0f} s: is causal-estimator running on domain {} with the same "
                  "transport profile?",
                  options_.wait_timeout_s, participant_.domain_id());
  }
  if (ok && !first) spdlog::info("readers are back: resuming");
  return ok;
}

void ReplayNode::stop() {
  stop_.store(true);
  wake_.notify_all();
}

void ReplayNode::check_names(const std::vector<std::string>& channel_names) const {
  // Channel names from the source file meet the one name limit (causal/io/name_limits.hpp) here, where they enter,
  // not at every reader of the frames (which would refuse them all).
  for (const auto& name : channel_names) {
    if (const char* problem = io::name_problem(name)) {
      throw io::InputError(options_.path, 0,
                           "channel name '" + name.substr(0, 40) + (name.size() > 40 ? "..." : "") + "' is " + problem +
                               " (names are 1 to " + std::to_string(io::kMaxNameBytes) + " bytes)");
    }
  }
}

int ReplayNode::run() {
  started_ = Clock::now();
  last_progress_ = started_;
  const bool ready = frames_ ? readers_present(*frames_, true) : readers_present(*conditions_, true);
  if (!ready) return stop_.load() ? config::kExitOk : config::kExitNoPeer;
  try {
    if (options_.source == SourceKind::FeatureTable) return run_features();
    const auto source = options_.source == SourceKind::ImsDirectory
                            ? open_ims_directory(options_.path, options_.channels, options_.channel_names)
                            : open_channel_csv(options_.path, options_.channels, options_.channel_names);
    check_names(source->channel_names());
    return run_raw(*source);
  } catch (const io::InputError& e) {
    spdlog::error("bad input: {}", e.what());
    return config::kExitFailed;
  } catch (const std::invalid_argument& e) {
    spdlog::error("{}", e.what());
    return config::kExitFailed;
  }
}

bool ReplayNode::pace(std::int64_t plant_ns) {
  if (!origin_set_) {
    origin_set_ = true;
    plant_origin_ns_ = plant_ns;
    wall_origin_ = Clock::now();
  }
  if (options_.speed <= 0.0) return !stop_.load();
  const double wall_offset_s = static_cast<double>(plant_ns - plant_origin_ns_) * 1e-9 / options_.speed;
  const auto due = wall_origin_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wall_offset_s));
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait_until(lock, due, [this] { return stop_.load(); });
  return !stop_.load();
}

void ReplayNode::report_progress(std::size_t done, std::size_t total, bool force) {
  if (!force && seconds_since(last_progress_) < options_.progress_every_s) return;
  last_progress_ = Clock::now();
  const double elapsed = seconds_since(started_);
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
  spdlog::info("progress: {}/{} snapshots, {:.1f} snapshots/s, ETA {:.0f} s", done, total, rate, eta);
}

int ReplayNode::run_raw(const SnapshotSource& source) {
  const std::size_t first = std::min(options_.first_snapshot, source.size());
  std::size_t last = source.size();
  if (options_.max_snapshots > 0) last = std::min(last, first + options_.max_snapshots);
  const std::size_t total = last - first;
  spdlog::info("replaying {} snapshot(s) of {} from {} as asset group '{}', channels [{}], {} samples per frame, "
               "speed {}",
               total, source.size(), options_.path, options_.asset_group, fmt::join(source.channel_names(), ", "),
               options_.frame_samples, options_.speed > 0 ? fmt::format("x{}", options_.speed) : "as fast as possible");

  causal_twin::VibrationFrame frame;
  dds::FrameHeader header;
  header.asset_group = options_.asset_group;
  header.sample_rate_hz = options_.sample_rate_hz;
  header.channel_names = source.channel_names();
  header.unit = options_.unit;
  std::uint64_t frames_sent = 0, samples_sent = 0, snapshots_sent = 0;
  const double sample_period_ns = 1e9 / options_.sample_rate_hz;

  std::vector<std::uint64_t> snapshot_start(last, 0);  // first sample index of every snapshot sent
  for (std::size_t i = first; i < last && !stop_.load(); ++i) {
    if (!readers_present(*frames_, false)) return stop_.load() ? config::kExitOk : config::kExitNoPeer;
    if (const auto resume = rewind_point(*frames_, first, i)) {
      i = *resume;
      header.first_sample_index = snapshot_start[i];
    }
    snapshot_start[i] = header.first_sample_index;
    const Snapshot snap = source.load(i);
    const Eigen::Index n = snap.samples.rows();
    header.source = snap.name;
    for (Eigen::Index row = 0; row < n && !stop_.load(); row += options_.frame_samples) {
      const Eigen::Index rows = std::min<Eigen::Index>(options_.frame_samples, n - row);
      header.first_sample_time_ns = snap.time_ns + static_cast<std::int64_t>(static_cast<double>(row) * sample_period_ns);
      header.discontinuity = (row == 0);  // every snapshot starts a new contiguous segment
      header.end_of_segment = (row + rows == n);
      if (!pace(header.first_sample_time_ns)) break;
      header.snapshot_index = i;
      dds::to_frame(header, snap.samples, row, rows, frame);
      const auto result = frames_->write(frame, stop_);
      if (result == dds::WriteResult::Stopped) break;
      if (result != dds::WriteResult::Ok) {
        spdlog::error("could not publish frame {} of '{}': {}", header.sequence, snap.name,
                      result == dds::WriteResult::TimedOut
                          ? "readers stopped acknowledging (timed out)"
                          : fmt::format("DDS write error, return code {}", frames_->last_error()));
        return config::kExitFailed;
      }
      ++header.sequence;
      header.first_sample_index += static_cast<std::uint64_t>(rows);
      ++frames_sent;
      samples_sent += static_cast<std::uint64_t>(rows);
    }
    ++snapshots_sent;
    spdlog::debug("snapshot {} ({}) published", snap.name, io::format_utc(snap.time_ns));
    report_progress(i + 1 - first, total, false);
  }
  report_progress(total, total, true);
  // Nothing is lost on exit: wait until every reader has acknowledged every frame.
  if (!frames_->wait_for_acknowledgments(std::chrono::seconds(30))) {
    spdlog::warn("not every frame was acknowledged within 30 s");
  }
  spdlog::info("published {} frames ({} samples per channel) in {:.2f} s{}", frames_sent, samples_sent,
               seconds_since(started_), stop_.load() ? " (stopped early)" : "");
  spdlog::info("summary topic=causal_twin/vibration_frame sent={} snapshots={} rewinds={}", frames_sent, snapshots_sent,
               rewinds_);
  return config::kExitOk;
}

int ReplayNode::run_features() {
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
  std::vector<bool> after_gap(table.time_ns.size(), false);
  for (const std::size_t r : gaps.rows) {
    after_gap[r] = true;
    spdlog::info("time gap of {} before snapshot {} ({} after {}; usual interval {}, gaps are > {} x that): published "
                 "as a discontinuity",
                 duration_text(table.time_ns[r] - table.time_ns[r - 1]), r, io::format_utc(table.time_ns[r]),
                 io::format_utc(table.time_ns[r - 1]), duration_text(gaps.median_interval_ns), options_.gap_factor);
  }
  const Eigen::MatrixXd values = select_channels(table.values, options_.channels);
  dds::ConditionHeader header;
  header.asset_group = options_.asset_group;
  header.feature = options_.feature_name;
  header.channel_names = select_names(table.channel_names, options_.channels, options_.channel_names);
  check_names(header.channel_names);
  const std::size_t rows = static_cast<std::size_t>(values.rows());
  const std::size_t first = std::min(options_.first_snapshot, rows);
  std::size_t last = rows;
  if (options_.max_snapshots > 0) last = std::min(last, first + options_.max_snapshots);
  spdlog::info("replaying {} condition vector(s) of {} ('{}') from {} as asset group '{}'", last - first, rows,
               header.feature, options_.path, options_.asset_group);
  causal_twin::ConditionVector out;
  std::size_t sent = 0;
  for (std::size_t i = first; i < last && !stop_.load(); ++i) {
    if (!readers_present(*conditions_, false)) return stop_.load() ? config::kExitOk : config::kExitNoPeer;
    if (const auto resume = rewind_point(*conditions_, first, i)) i = *resume;
    header.snapshot_index = i;
    header.time_ns = table.time_ns[i];
    header.discontinuity = (i == first) || after_gap[i];
    if (!pace(header.time_ns)) break;
    dds::to_condition_vector(header, values.row(static_cast<Eigen::Index>(i)).transpose(), out);
    const auto result = conditions_->write(out, stop_);
    if (result == dds::WriteResult::Stopped) break;
    if (result != dds::WriteResult::Ok) {
      spdlog::error("could not publish condition vector {}: readers stopped acknowledging", i);
      return config::kExitFailed;
    }
    ++sent;
    report_progress(sent, last - first, false);
  }
  report_progress(sent, last - first, true);
  if (!conditions_->wait_for_acknowledgments(std::chrono::seconds(30))) {
    spdlog::warn("not every condition vector was acknowledged within 30 s");
  }
  spdlog::info("published {} condition vectors in {:.2f} s{}", sent, seconds_since(started_),
               stop_.load() ? " (stopped early)" : "");
  spdlog::info("summary topic=causal_twin/condition_input sent={} rewinds={} time_gaps={}", sent, rewinds_,
               gaps.rows.size());
  return config::kExitOk;
}

}  // namespace causal::replay
