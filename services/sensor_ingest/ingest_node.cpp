#include "ingest_node.hpp"

#include "causal/dds/peer_wait.hpp"

#include <spdlog/spdlog.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <numeric>

#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/stop_timer.hpp"
#include "causal/dds/topics.hpp"
#include "causal/config/exit_codes.hpp"

namespace causal::ingest {

bool RateLimitedLog::allow(std::uint64_t& suppressed) {
  constexpr std::uint64_t kFirst = 5;
  constexpr auto kInterval = std::chrono::seconds(10);
  const auto now = std::chrono::steady_clock::now();
  ++seen_;
  if (seen_ <= kFirst || now - last_ >= kInterval) {
    suppressed = skipped_;
    skipped_ = 0;
    last_ = now;
    return true;
  }
  ++skipped_;
  return false;
}

namespace {
std::uint64_t total(const std::array<std::uint64_t, kRejectReasonCount>& a) {
  return std::accumulate(a.begin(), a.end(), std::uint64_t{0});
}
std::string suppressed_text(std::uint64_t n) { return n > 0 ? fmt::format(" ({} more like it not logged)", n) : ""; }
}  // namespace

IngestNode::IngestNode(IngestOptions options)
    : options_(std::move(options)),
      participant_(dds::to_dds_settings(options_.dds, "sensor-ingest")),
      frames_(participant_, dds::topics::kVibrationFrame, dds::profiles::kVibrationFrameWriter),
      queue_(options_.queue_messages),
      sequencer_(options_.gap_factor),
      numbering_(options_.state_dir),
      features_(participant_, dds::topics::kConditionInput, dds::profiles::kConditionInputWriter),
      backlog_(options_.backlog_frames),
      progress_(participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorReader) {
  for (const auto& w : options_.wait_for) reader_names_.push_back(dds::parse_named_readers(w).name);
  if (reader_names_.empty()) reader_names_.push_back("causal-estimator");
  auto& m = metrics::process_metrics();
  const metrics::Labels source{{"source", source_kind_name(options_.source.kind)}};
  received_metric_ =
      &m.counter("ingest_messages_received_total", "Messages sensor-ingest took from its source", source);
  published_metric_ = &m.counter("ingest_frames_published_total", "Vibration frames sensor-ingest published", source);
  lost_metric_ = &m.counter("ingest_frames_lost_total", "Frames the DDS readers did not accept in time", source);
  non_finite_metric_ = &m.counter("ingest_non_finite_values_total",
                                  "NaN/Inf sample values forwarded (the estimator screens them)", source);
  missed_metric_ = &m.counter("ingest_blocks_missed_total",
                              "Source blocks that never reached sensor-ingest across its restart (lost)", source);
  discontinuity_metric_ =
      &m.counter("ingest_discontinuities_total",
                 "Frames flagged as a discontinuity (first block, source gap, restart, new segment)", source);
  for (int r = 0; r < kRejectReasonCount; ++r) {
    metrics::Labels labels = source;
    labels["reason"] = reason_name(static_cast<RejectReason>(r));
    rejected_metric_[static_cast<std::size_t>(r)] =
        &m.counter("ingest_messages_rejected_total", "Messages sensor-ingest rejected, by reason", labels);
  }
  source_ = make_source(options_, queue_);
}

IngestNode::~IngestNode() {
  queue_.close();  // a source blocked on a full queue returns before it is stopped
  source_->stop();
}

void IngestNode::stop() {
  stop_.store(true);
  queue_.close();
}

int IngestNode::run() {
  const auto started = Clock::now();
  dds::StopTimer runtime_limit(options_.max_runtime_s, [this] {
    spdlog::warn("max runtime {:.1f} s reached: stopping", options_.max_runtime_s);
    stop();
  });
  if (options_.max_runtime_s > 0) {
    deadline_ =
        started + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.max_runtime_s));
  }
  if (options_.wait_subscribers > 0 || !options_.wait_for.empty()) {
    const std::string what = fmt::format("{} reader(s){}{} on domain {}", options_.wait_subscribers,
                                         options_.wait_for.empty() ? "" : " including ", fmt::join(options_.wait_for, ", "),
                                         participant_.domain_id());
    spdlog::info("waiting {} for {}", options_.wait_timeout_s > 0 ? fmt::format("up to {:.0f} s", options_.wait_timeout_s)
                                                                   : std::string("for as long as it takes"), what);
    std::vector<dds::NamedReaders> named;
    for (const auto& w : options_.wait_for) named.push_back(dds::parse_named_readers(w));
    const auto ready = [&](std::chrono::milliseconds limit) {
      return frames_.wait_for_readers(static_cast<std::size_t>(options_.wait_subscribers), limit, stop_) &&
             dds::wait_for_named_readers(frames_, named, limit, stop_).empty();
    };
    if (!dds::wait_for_peers(ready, options_.wait_timeout_s, stop_, what)) {
      print_summary();
      if (stop_.load()) return 0;
      spdlog::error(
          "no reader matched within {:.0f} s: is causal-estimator running on domain {} with the same "
          "transport profile?",
          options_.wait_timeout_s, participant_.domain_id());
      return config::kExitNoPeer;
    }
  }
  spdlog::info("ingesting from {} ({}); backlog {} frames per asset group for a restarted estimator",
               options_.source.text, source_kind_name(options_.source.kind), options_.backlog_frames);
  resend_to_new_readers();  // the first look: the readers present now are not new
  source_->start();
  // Until the source ends (stdin) or a stop; after a stop the messages already queued are still published.
  while (true) {
    auto message = queue_.pop(std::chrono::milliseconds(200));
    resend_to_new_readers();
    if (!message) {
      if (queue_.closed_and_empty()) break;
      continue;
    }
    process(*message);
  }
  source_->stop();
  auto ack_wait =
      std::chrono::duration_cast<Clock::duration>(stop_.load() ? std::chrono::seconds(2) : std::chrono::seconds(30));
  if (deadline_ != Clock::time_point::max())
    ack_wait = std::min(ack_wait, std::max(Clock::duration::zero(), deadline_ - Clock::now()));
  if (!frames_.wait_for_acknowledgments(std::chrono::duration_cast<std::chrono::milliseconds>(ack_wait)) ||
      !features_.wait_for_acknowledgments(std::chrono::duration_cast<std::chrono::milliseconds>(ack_wait))) {
    spdlog::warn("not every frame was acknowledged by the readers within {:.1f} s",
                 std::chrono::duration<double>(ack_wait).count());
  }
  spdlog::info("{} messages in, {} frames published in {:.2f} s{}", received_, published_,
               std::chrono::duration<double>(Clock::now() - started).count(), stop_.load() ? " (stopped)" : "");
  print_summary();
  return total(rejected_) + lost_ + missed_ > 0 ? config::kExitLostOrRefused : config::kExitOk;
}

void IngestNode::count_rejection(RejectReason reason, const std::string& detail, const std::string& group) {
  const auto r = static_cast<std::size_t>(reason);
  ++rejected_[r];
  rejected_metric_[r]->inc();
  std::uint64_t suppressed = 0;
  if (reject_log_[r].allow(suppressed)) {
    spdlog::warn("message {} rejected ({}){}: {}{}", received_, reason_name(reason),
                 group.empty() ? "" : fmt::format(" for '{}'", group), detail, suppressed_text(suppressed));
  }
}

void IngestNode::process(const std::string& message) {
  ++received_;
  received_metric_->inc();
  if (is_feature_row(message)) {
    process_features(message);
    return;
  }
  ParseResult parsed = parse_block(message, options_.limits);
  if (!parsed.block) {
    count_rejection(parsed.reason, parsed.detail, "");
    return;
  }
  const IngestBlock& b = *parsed.block;
  // Limits every reader applies (frame_conversions.hpp InputLimits), checked before the block takes a number.
  if (const std::string problem = dds::validate_frame_header(b.channels.size(), b.sample_rate_hz, b.t0_ns);
      !problem.empty()) {
    count_rejection(RejectReason::Field, problem, b.asset_group);
    return;
  }
  if (!sequencer_.knows(b.asset_group) && !resume_numbering(b.asset_group)) {
    count_rejection(RejectReason::Field, "the asset group's numbering state cannot be read", b.asset_group);
    return;
  }
  const Admission admission = sequencer_.admit(b);
  if (!admission.plan) {
    count_rejection(admission.reason, admission.detail, b.asset_group);
    return;
  }
  const FramePlan& plan = *admission.plan;
  std::uint64_t suppressed = 0;
  // Saved before the frame leaves: a crash may leave a number unused (counted as lost), never one used twice.
  if (!numbering_.save(b.asset_group, *sequencer_.resume_point(b.asset_group)) && numbering_log_.allow(suppressed)) {
    spdlog::error("'{}': numbering state not written ({}): a restart now would number this group's frames again "
                  "from an older point{}", b.asset_group, numbering_.last_error(), suppressed_text(suppressed));
  }
  if (b.non_finite > 0) {
    non_finite_ += b.non_finite;
    non_finite_metric_->inc(static_cast<double>(b.non_finite));
    if (non_finite_log_.allow(suppressed)) {
      spdlog::warn("'{}' block {}: {} non-finite value(s) forwarded (the estimator rejects and counts them){}",
                   b.asset_group, b.sequence, b.non_finite, suppressed_text(suppressed));
    }
  }
  if (plan.missed > 0) {
    missed_ += plan.missed;
    missed_metric_->inc(static_cast<double>(plan.missed));
    spdlog::error("'{}': {} source blocks before block {} never reached sensor-ingest (sent while it was down, or "
                  "inside the process that was killed): lost; frames {}..{} are skipped, so the estimator counts them",
                  b.asset_group, plan.missed, b.sequence, plan.sequence - plan.missed, plan.sequence - 1);
  }
  if (plan.discontinuity) {
    ++discontinuities_;
    discontinuity_metric_->inc();
    if (discontinuity_log_.allow(suppressed)) {
      spdlog::info("'{}' frame {} (source block {}) starts a new segment, snapshot {}: {}{}", b.asset_group,
                   plan.sequence, b.sequence, plan.snapshot_index, plan.why, suppressed_text(suppressed));
    }
  }
  dds::FrameHeader h;
  h.asset_group = b.asset_group;
  h.sequence = plan.sequence;
  h.first_sample_index = plan.first_sample_index;
  h.snapshot_index = plan.snapshot_index;
  h.first_sample_time_ns = b.t0_ns;
  h.sample_rate_hz = b.sample_rate_hz;
  h.channel_names = b.channels;
  h.unit = b.unit;
  h.discontinuity = plan.discontinuity;
  h.end_of_segment = b.end_of_segment;
  h.source = fmt::format("{} block {}", options_.source.text, b.sequence);
  const auto rows = static_cast<Eigen::Index>(b.samples_per_channel);
  const Eigen::MatrixXd block =
      Eigen::Map<const dds::RowMajorMatrix>(b.samples.data(), rows, static_cast<Eigen::Index>(b.channels.size()));
  dds::to_frame(h, block, 0, rows, frame_);
  const auto write_deadline = std::min(Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                          std::chrono::duration<double>(options_.write_timeout_s)),
                                       deadline_);
  const auto result = frames_.write_until(frame_, stop_, write_deadline);
  if (result == dds::WriteResult::Ok) {
    ++published_;
    published_metric_->inc();
    backlog_.keep(frame_);
    return;
  }
  // The frame's sequence number stays used: the readers see the gap, as the IDL says for lost frames.
  ++lost_;
  lost_metric_->inc();
  spdlog::error("'{}' frame {} lost: {}", b.asset_group, plan.sequence,
                result == dds::WriteResult::Stopped ? std::string("stopping while the readers were behind")
                : result == dds::WriteResult::TimedOut
                    ? fmt::format("not accepted within {:.1f} s", options_.write_timeout_s)
                    : fmt::format("DDS write error, return code {}", frames_.last_error()));
}

void IngestNode::resend_to_new_readers() {
  progress_.take_all([this](const causal_twin::ConditionVector& c, const auto&) {
    auto [it, added] = estimator_published_.emplace(c.asset_group(), c.snapshot_index());
    if (!added && c.snapshot_index() > it->second) it->second = c.snapshot_index();
  });
  const auto now = Clock::now();
  const bool first_look = last_look_ == Clock::time_point{};
  if (!first_look && now - last_look_ < std::chrono::milliseconds(100)) return;
  last_look_ = now;
  std::size_t named = 0, matched = 0;
  for (const auto& name : reader_names_) {
    for (const auto& guid : frames_.readers_named(name)) {
      ++named;
      if (known_readers_.insert(guid).second && !first_look) new_readers_.insert(guid);
    }
    matched += frames_.matched_readers_named(name);
  }
  // Resent once every reader discovered is matched: frames written before the match would not reach it.
  if (new_readers_.empty() || matched < named || !backlog_.enabled()) return;
  new_readers_.clear();
  ++resends_;
  for (const auto& group : backlog_.groups()) resend_group(group);
}

void IngestNode::resend_group(const std::string& group) {
  const auto it = estimator_published_.find(group);
  const std::optional<std::uint64_t> after =
      it == estimator_published_.end() ? std::nullopt : std::optional(it->second);
  const auto frames = backlog_.after(group, after);
  const auto oldest = backlog_.oldest_snapshot(group);
  if (after && oldest && *oldest > *after + 1) {
    // Older than the backlog: the estimator sees the gap in the snapshot indices and counts it as lost.
    beyond_backlog_ += *oldest - *after - 1;
    spdlog::error("'{}': a new {} needs snapshots from {}, the backlog ({} frames) starts at snapshot {}: "
                  "snapshots {}..{} cannot be resent (the estimator counts them as lost)",
                  group, fmt::join(reader_names_, "/"), *after + 1, backlog_.capacity(), *oldest, *after + 1,
                  *oldest - 1);
  }
  if (frames.empty()) return;
  spdlog::warn("'{}': a new {} appeared (a restart?): resending {} kept frames from snapshot {} (the last one "
               "published for it was {})",
               group, fmt::join(reader_names_, "/"), frames.size(), frames.front()->snapshot_index(),
               after ? std::to_string(*after) : std::string("none"));
  for (const auto* f : frames) {
    auto copy = *f;
    const auto deadline = std::min(Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                      std::chrono::duration<double>(options_.write_timeout_s)),
                                   deadline_);
    const auto result = frames_.write_until(copy, stop_, deadline);
    if (result == dds::WriteResult::Ok) {
      ++resent_;
      continue;
    }
    ++lost_;
    lost_metric_->inc();
    spdlog::error("'{}' frame {} not resent: the readers did not accept it", group, f->sequence_number());
  }
}

void IngestNode::process_features(const std::string& message) {
  const FeatureParseResult parsed = parse_feature_row(message, options_.limits);
  if (!parsed.row) {
    count_rejection(parsed.reason, parsed.detail, "");
    return;
  }
  const FeatureRow& r = *parsed.row;
  if (!features_ready_) {
    // The readers waited for at the start were the frames' ones: before the first feature row, the same wait on
    // the condition-input topic (an estimator has both readers; a row written before the match would be lost).
    features_ready_ = true;
    std::vector<dds::NamedReaders> named;
    for (const auto& w : options_.wait_for) named.push_back(dds::parse_named_readers(w));
    const auto limit = std::chrono::milliseconds(static_cast<long>(1000 * (options_.wait_timeout_s > 0 ? options_.wait_timeout_s : 30.0)));
    if (!features_.wait_for_readers(static_cast<std::size_t>(options_.wait_subscribers), limit, stop_) ||
        !dds::wait_for_named_readers(features_, named, limit, stop_).empty()) {
      spdlog::warn("no reader of causal_twin/condition_input matched within {} ms: feature rows go out anyway",
                   limit.count());
    }
  }
  auto [it, first] = feature_streams_.try_emplace(r.asset_group);
  FeatureStream& s = it->second;
  if (!first && (r.channels != s.channels || r.feature != s.feature)) {
    count_rejection(RejectReason::LayoutChange, "channels or feature differ from this group's earlier rows", r.asset_group);
    return;
  }
  if (!first && r.sequence <= s.last_sequence) {
    count_rejection(r.sequence == s.last_sequence ? RejectReason::Duplicate : RejectReason::OutOfOrder,
                    fmt::format("sequence {} after {}", r.sequence, s.last_sequence), r.asset_group);
    return;
  }
  if (!first && r.time_ns <= s.last_time_ns) {
    count_rejection(RejectReason::OutOfOrder, "time does not advance", r.asset_group);
    return;
  }
  if (r.non_finite > 0) {
    non_finite_ += r.non_finite;
    non_finite_metric_->inc(static_cast<double>(r.non_finite));
  }
  feature_msg_.asset_group(r.asset_group);
  feature_msg_.feature(r.feature);
  feature_msg_.snapshot_index(r.sequence);  // the source's snapshot counter: gaps are lost rows, counted downstream
  feature_msg_.time_ns(r.time_ns);
  feature_msg_.channel_names(r.channels);
  feature_msg_.values(r.values);
  feature_msg_.discontinuity(r.discontinuity || first);
  const auto deadline = std::min(Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                    std::chrono::duration<double>(options_.write_timeout_s)),
                                 deadline_);
  const auto result = features_.write_until(feature_msg_, stop_, deadline);
  s.channels = r.channels;
  s.feature = r.feature;
  s.last_sequence = r.sequence;
  s.last_time_ns = r.time_ns;
  if (result == dds::WriteResult::Ok) {
    ++published_;
    ++features_published_;
    published_metric_->inc();
    return;
  }
  ++lost_;
  lost_metric_->inc();
  spdlog::error("'{}' feature row {} lost: the readers did not accept it", r.asset_group, r.sequence);
}

bool IngestNode::resume_numbering(const std::string& group) {
  try {
    const auto point = numbering_.load(group);
    if (!point) return true;
    sequencer_.resume(group, *point);
    ++resumed_groups_;
    spdlog::info("'{}': numbering resumed from {}: next frame {}, next sample {}, snapshot {} (a restart: the "
                 "estimator would refuse frames numbered from 0 again)",
                 group, numbering_.path(group), point->next_sequence, point->next_sample_index,
                 point->snapshot_index + 1);
    return true;
  } catch (const std::exception& e) {
    spdlog::error("'{}': {}", group, e.what());
    return false;
  }
}

void IngestNode::print_summary() const {
  const std::uint64_t rejected = total(rejected_);
  spdlog::info("summary topic=causal_twin/vibration_frame sent={} received={} rejected={} failed={}", published_,
               received_, rejected, lost_);
  // Machine-readable, on stdout, outside the log pattern.
  std::string reasons;
  for (int r = 0; r < kRejectReasonCount; ++r) {
    reasons += fmt::format(" {}={}", reason_name(static_cast<RejectReason>(r)), rejected_[static_cast<std::size_t>(r)]);
  }
  std::printf(
      "sensor-ingest: received=%llu published=%llu rejected=%llu lost=%llu non_finite=%llu discontinuities=%llu "
      "resumed_groups=%llu state_failures=%llu resent=%llu resends=%llu beyond_backlog=%llu feature_rows=%llu%s "
      "missed=%llu\n",
      static_cast<unsigned long long>(received_), static_cast<unsigned long long>(published_),
      static_cast<unsigned long long>(rejected), static_cast<unsigned long long>(lost_),
      static_cast<unsigned long long>(non_finite_), static_cast<unsigned long long>(discontinuities_),
      static_cast<unsigned long long>(resumed_groups_), static_cast<unsigned long long>(numbering_.failures()),
      static_cast<unsigned long long>(resent_), static_cast<unsigned long long>(resends_),
      static_cast<unsigned long long>(beyond_backlog_), static_cast<unsigned long long>(features_published_),
      reasons.c_str(), static_cast<unsigned long long>(missed_));
  std::fflush(stdout);
}

}  // namespace causal::ingest
