#include "ingest_node.hpp"

#include "causal/dds/peer_wait.hpp"

#include <spdlog/spdlog.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <numeric>

#include "causal/dds/frame_conversions.hpp"

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

std::vector<std::string> restart_readers(const IngestOptions& o) {
  std::vector<std::string> names;
  for (const auto& w : o.wait.wait_for) names.push_back(dds::parse_named_readers(w).name);
  if (names.empty()) names.push_back("causal-estimator");
  return names;
}

dds::SourceDriverOptions driver_options(const IngestOptions& o) {
  dds::SourceDriverOptions d;
  d.wait = o.wait;
  d.frames = true;
  d.conditions = true;  // feature rows
  d.restart_readers = restart_readers(o);
  d.write_timeout_s = o.write_timeout_s;
  d.max_runtime_s = o.max_runtime_s;
  d.drain_after_stop = true;  // what the source already took is published (or counted lost) after a stop
  return d;
}
}  // namespace

IngestNode::IngestNode(IngestOptions options)
    : options_(std::move(options)),
      participant_(dds::to_dds_settings(options_.dds, "sensor-ingest")),
      driver_(participant_, driver_options(options_)),
      queue_(options_.queue_messages),
      sequencer_(options_.gap_factor),
      numbering_(options_.state_dir),
      backlog_(options_.backlog_frames),
      reader_names_(restart_readers(options_)) {
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
  driver_.stop();
  queue_.close();
}

void IngestNode::start(dds::SourceDriver& driver) {
  running_ = &driver;
  spdlog::info("ingesting from {} ({}); backlog {} frames per asset group for a restarted estimator",
               options_.source.text, source_kind_name(options_.source.kind), options_.backlog_frames);
  source_->start();
}

dds::Take IngestNode::next(dds::SourceDriver& driver, dds::SourceBlock& out) {
  // Until the source ends (stdin) or a stop; after a stop the messages already queued are still published.
  while (true) {
    if (!pending_.empty()) {
      out.kind = dds::SourceBlock::Kind::Kept;
      out.kept = pending_.front();
      pending_.pop_front();
      return dds::Take::Block;
    }
    if (!holding_) {
      held_ = queue_.pop(std::chrono::milliseconds(200));
      holding_ = true;
      if (const auto published = driver.restarted()) resend(*published);
      if (!pending_.empty()) continue;  // the kept frames first, then this message
    }
    holding_ = false;
    auto message = std::move(held_);
    held_.reset();
    if (!message && queue_.closed_and_empty()) {
      source_->stop();
      return dds::Take::End;
    }
    if (!message) return dds::Take::Idle;
    return process(*message, out) ? dds::Take::Block : dds::Take::Idle;
  }
}

std::uint64_t IngestNode::refused() const { return total(rejected_) + missed_; }

void IngestNode::written(const dds::SourceBlock& block, dds::WriteResult result,
                         const causal_twin::VibrationFrame* built) {
  if (block.kind == dds::SourceBlock::Kind::Kept) {
    if (result != dds::WriteResult::Ok) lost_metric_->inc();
    return;
  }
  if (result != dds::WriteResult::Ok) {
    // The frame's sequence number stays used: the readers see the gap, as the IDL says for lost frames.
    lost_metric_->inc();
    return;
  }
  ++published_;
  published_metric_->inc();
  if (block.kind == dds::SourceBlock::Kind::Condition) {
    ++features_published_;
  } else {
    backlog_.keep(*built);
  }
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

bool IngestNode::process(const std::string& message, dds::SourceBlock& out) {
  ++received_;
  received_metric_->inc();
  if (is_feature_row(message)) return process_features(message, out);
  ParseResult parsed = parse_block(message, options_.limits);
  if (!parsed.block) {
    count_rejection(parsed.reason, parsed.detail, "");
    return false;
  }
  const IngestBlock& b = *parsed.block;
  // Limits every reader applies (frame_conversions.hpp InputLimits), checked before the block takes a number.
  if (const std::string problem = dds::validate_frame_header(b.channels.size(), b.sample_rate_hz, b.t0_ns);
      !problem.empty()) {
    count_rejection(RejectReason::Field, problem, b.asset_group);
    return false;
  }
  if (!sequencer_.knows(b.asset_group) && !resume_numbering(b.asset_group)) {
    count_rejection(RejectReason::Field, "the asset group's numbering state cannot be read", b.asset_group);
    return false;
  }
  const Admission admission = sequencer_.admit(b);
  if (!admission.plan) {
    count_rejection(admission.reason, admission.detail, b.asset_group);
    return false;
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
  out.kind = dds::SourceBlock::Kind::Frame;
  out.numbered = true;  // the sequencer's numbers: a restart or a missed block keeps its place
  dds::FrameHeader& h = out.frame;
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
  block_ = Eigen::Map<const dds::RowMajorMatrix>(b.samples.data(), rows, static_cast<Eigen::Index>(b.channels.size()));
  out.samples = &block_;
  out.first_row = 0;
  out.rows = rows;
  return true;
}

void IngestNode::resend(const dds::PublishedSnapshots& published) {
  if (!backlog_.enabled()) return;
  ++resends_;
  for (const auto& group : backlog_.groups()) resend_group(group, published);
}

void IngestNode::resend_group(const std::string& group, const dds::PublishedSnapshots& published) {
  const auto it = published.find(group);
  const std::optional<std::uint64_t> after = it == published.end() ? std::nullopt : std::optional(it->second);
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
  pending_.insert(pending_.end(), frames.begin(), frames.end());
}

bool IngestNode::process_features(const std::string& message, dds::SourceBlock& out) {
  const FeatureParseResult parsed = parse_feature_row(message, options_.limits);
  if (!parsed.row) {
    count_rejection(parsed.reason, parsed.detail, "");
    return false;
  }
  const FeatureRow& r = *parsed.row;
  auto [it, first] = feature_streams_.try_emplace(r.asset_group);
  FeatureStream& s = it->second;
  if (!first && (r.channels != s.channels || r.feature != s.feature)) {
    count_rejection(RejectReason::LayoutChange, "channels or feature differ from this group's earlier rows", r.asset_group);
    return false;
  }
  if (!first && r.sequence <= s.last_sequence) {
    count_rejection(r.sequence == s.last_sequence ? RejectReason::Duplicate : RejectReason::OutOfOrder,
                    fmt::format("sequence {} after {}", r.sequence, s.last_sequence), r.asset_group);
    return false;
  }
  if (!first && r.time_ns <= s.last_time_ns) {
    count_rejection(RejectReason::OutOfOrder, "time does not advance", r.asset_group);
    return false;
  }
  if (r.non_finite > 0) {
    non_finite_ += r.non_finite;
    non_finite_metric_->inc(static_cast<double>(r.non_finite));
  }
  s.channels = r.channels;
  s.feature = r.feature;
  s.last_sequence = r.sequence;
  s.last_time_ns = r.time_ns;
  out.kind = dds::SourceBlock::Kind::Condition;
  out.condition.asset_group = r.asset_group;
  out.condition.feature = r.feature;
  out.condition.snapshot_index = r.sequence;  // the source's snapshot counter: gaps are lost rows, counted downstream
  out.condition.time_ns = r.time_ns;
  out.condition.channel_names = r.channels;
  out.condition.discontinuity = r.discontinuity || first;
  out.values = Eigen::Map<const Eigen::VectorXd>(r.values.data(), static_cast<Eigen::Index>(r.values.size()));
  return true;
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

void IngestNode::summary(const dds::SourceCounts& counts, bool stopped) const {
  if (running_) {
    spdlog::info("{} messages in, {} frames published in {:.2f} s{}", received_, published_, running_->elapsed_s(),
                 stopped ? " (stopped)" : "");
  }
  const std::uint64_t rejected = total(rejected_);
  spdlog::info("summary topic=causal_twin/vibration_frame sent={} received={} rejected={} failed={}", published_,
               received_, rejected, counts.lost);
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
      static_cast<unsigned long long>(rejected), static_cast<unsigned long long>(counts.lost),
      static_cast<unsigned long long>(non_finite_), static_cast<unsigned long long>(discontinuities_),
      static_cast<unsigned long long>(resumed_groups_), static_cast<unsigned long long>(numbering_.failures()),
      static_cast<unsigned long long>(counts.resent), static_cast<unsigned long long>(resends_),
      static_cast<unsigned long long>(beyond_backlog_), static_cast<unsigned long long>(features_published_),
      reasons.c_str(), static_cast<unsigned long long>(missed_));
  std::fflush(stdout);
}

}  // namespace causal::ingest
