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
      sequencer_(options_.gap_factor) {
  auto& m = metrics::process_metrics();
  const metrics::Labels source{{"source", source_kind_name(options_.source.kind)}};
  received_metric_ =
      &m.counter("ingest_messages_received_total", "Messages sensor-ingest took from its source", source);
  published_metric_ = &m.counter("ingest_frames_published_total", "Vibration frames sensor-ingest published", source);
  lost_metric_ = &m.counter("ingest_frames_lost_total", "Frames the DDS readers did not accept in time", source);
  non_finite_metric_ = &m.counter("ingest_non_finite_values_total",
                                  "NaN/Inf sample values forwarded (the estimator screens them)", source);
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
      return 3;
    }
  }
  spdlog::info("ingesting from {} ({})", options_.source.text, source_kind_name(options_.source.kind));
  source_->start();
  // Until the source ends (stdin) or a stop; after a stop the messages already queued are still published.
  while (true) {
    auto message = queue_.pop(std::chrono::milliseconds(200));
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
  if (!frames_.wait_for_acknowledgments(std::chrono::duration_cast<std::chrono::milliseconds>(ack_wait))) {
    spdlog::warn("not every frame was acknowledged by the readers within {:.1f} s",
                 std::chrono::duration<double>(ack_wait).count());
  }
  spdlog::info("{} messages in, {} frames published in {:.2f} s{}", received_, published_,
               std::chrono::duration<double>(Clock::now() - started).count(), stop_.load() ? " (stopped)" : "");
  print_summary();
  return total(rejected_) + lost_ > 0 ? 4 : 0;
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
  ParseResult parsed = parse_block(message, options_.limits);
  if (!parsed.block) {
    count_rejection(parsed.reason, parsed.detail, "");
    return;
  }
  const IngestBlock& b = *parsed.block;
  const Admission admission = sequencer_.admit(b);
  if (!admission.plan) {
    count_rejection(admission.reason, admission.detail, b.asset_group);
    return;
  }
  const FramePlan& plan = *admission.plan;
  std::uint64_t suppressed = 0;
  if (b.non_finite > 0) {
    non_finite_ += b.non_finite;
    non_finite_metric_->inc(static_cast<double>(b.non_finite));
    if (non_finite_log_.allow(suppressed)) {
      spdlog::warn("'{}' block {}: {} non-finite value(s) forwarded (the estimator rejects and counts them){}",
                   b.asset_group, b.sequence, b.non_finite, suppressed_text(suppressed));
    }
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
      "sensor-ingest: received=%llu published=%llu rejected=%llu lost=%llu non_finite=%llu discontinuities=%llu%s\n",
      static_cast<unsigned long long>(received_), static_cast<unsigned long long>(published_),
      static_cast<unsigned long long>(rejected), static_cast<unsigned long long>(lost_),
      static_cast<unsigned long long>(non_finite_), static_cast<unsigned long long>(discontinuities_), reasons.c_str());
  std::fflush(stdout);
}

}  // namespace causal::ingest
