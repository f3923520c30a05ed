// causal-estimator, processing: the per-group pipelines, fed in order; their output handed to publishing.
#include "estimator_processing.hpp"

#include "causal/dds/frame_conversions.hpp"
#include "causal/io/time_format.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <stdexcept>

namespace causal::estimator {

void GroupState::note_input(std::int64_t source_time_ns) {
  last_arrival_ns->store(std::chrono::nanoseconds(std::chrono::steady_clock::now().time_since_epoch()).count(),
                         std::memory_order_relaxed);
  if (input_time != nullptr) input_time->set(static_cast<double>(source_time_ns) * 1e-9);
}

EstimatorProcessing::EstimatorProcessing(const EstimatorOptions& options, pipeline::AssetPipelineParams params,
                                         EstimatorPublisher& publisher)
    : options_(options), params_(std::move(params)), publisher_(publisher) {
  // Sample-level noise tuning (~18 ms per group at 4096 samples) runs on one worker thread: a group that is
  // still tuning buffers its frames and no other group's frames wait behind it. Same reports, later.
  if (params_.sample.noise.automatic) params_.sample.noise.worker = std::make_shared<pipeline::TuningWorker>();
}

GroupState& EstimatorProcessing::group(const std::string& name) {
  auto it = groups_.find(name);
  if (it != groups_.end()) return it->second;
  GroupState& a = groups_.emplace(name, GroupState(params_)).first->second;
  auto& m = metrics::process_metrics();
  const char* help = "Time to process one input of an asset group (filters, smoothers, output queued)";
  a.frame_seconds = &m.histogram("estimator_processing_seconds", help, {{"asset_group", name}, {"input", "frame"}},
                                 metrics::latency_buckets_seconds());
  a.condition_seconds = &m.histogram("estimator_processing_seconds", help,
                                     {{"asset_group", name}, {"input", "condition"}}, metrics::latency_buckets_seconds());
  a.input_age = m.gauge_callback(
      "estimator_input_age_seconds", "Seconds since the asset group's last input (frame or condition vector) arrived",
      {{"asset_group", name}}, [t = a.last_arrival_ns] {
        const std::int64_t last = t->load(std::memory_order_relaxed);
        const auto now = std::chrono::steady_clock::now().time_since_epoch();
        return last == 0 ? 0.0 : static_cast<double>(std::chrono::nanoseconds(now).count() - last) * 1e-9;
      });
  a.input_time = &m.gauge("estimator_last_input_timestamp_seconds",
                          "Source time (UTC, Unix seconds) of the asset group's last input: time() minus this is the "
                          "data's age",
                          {{"asset_group", name}});
  try {
    if (publisher_.restore(name, a)) {
      a.awaiting_continuation = true;
      a.continuation_deadline = std::chrono::steady_clock::now() +
                                std::chrono::milliseconds(static_cast<long>(options_.resume_wait_s * 1000));
      const auto& last = a.pipeline.last_source_index();
      spdlog::info("asset group '{}' resumed from checkpoint {}: last snapshot {}, last sample {}", name,
                   publisher_.checkpoint_path(name), last.has_snapshot ? std::to_string(last.snapshot) : "none",
                   last.has_sample ? std::to_string(last.sample) : "none");
    } else {
      spdlog::info("new asset group '{}'", name);
    }
  } catch (const std::exception& e) {
    // Only this asset group stops: the others carry on (bad input is isolated).
    a.refused = e.what();
    spdlog::error("asset group '{}': {}; its input is refused (counted) until this is fixed", name, e.what());
  }
  return a;
}

void EstimatorProcessing::feed_frame(const causal_twin::VibrationFrame& frame, GroupState& a, bool gap,
                                     const std::shared_ptr<StageTrace::Frame>& trace) {
  const std::string& name = frame.asset_group();
  if (a.channel_names.empty()) {
    a.channel_names = dds::channel_names(frame);
    a.pipeline.set_channel_names(a.channel_names);
  }
  out_.clear();
  const auto started = std::chrono::steady_clock::now();
  // Indices come from the source, so reports keep them across a restart or a lost frame.
  pipeline::FrameCheck check;
  try {
    check = a.pipeline.feed_frame(dds::samples_view(frame), frame.first_sample_index(), frame.snapshot_index(),
                                  frame.discontinuity(), frame.end_of_segment(), gap, frame.first_sample_time_ns(),
                                  frame.sample_rate_hz(), out_);
  } catch (const std::exception& e) {
    fail(name, a, e, frame.snapshot_index(), frame.first_sample_time_ns());
    return;
  }
  if (trace) trace->fed_ns = StageTrace::now_ns();
  if (!accepted(name, a, check, a.refused_frames, "frame", frame.sequence_number(), frame.snapshot_index(),
                frame.first_sample_time_ns())) {
    return;
  }
  ++a.frames;
  ++frames_fed_;
  a.last_time_ns = frame.first_sample_time_ns() +
                   static_cast<std::int64_t>(static_cast<double>(std::max<std::uint32_t>(frame.samples_per_channel(), 1) - 1) *
                                             1e9 / frame.sample_rate_hz());
  if (a.feature.empty()) a.feature = io::to_string(params_.condition.feature);
  publisher_.publish_quality(name, a, out_, frame.snapshot_index(), frame.first_sample_time_ns(), frame.end_of_segment());
  publisher_.publish(name, a, out_, frame.end_of_segment(), trace);
  if (!publisher_.standing_by()) log_learned(name, a);
  if (!a.startup_logged) log_startup_done(name, a);
  a.frame_seconds->observe(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
}

bool EstimatorProcessing::accepted(const std::string& name, GroupState& a, const pipeline::FrameCheck& check,
                                   std::uint64_t& refused, const char* kind, std::uint64_t number,
                                   std::uint64_t snapshot, std::int64_t time_ns) {
  if (!check.ok) {
    ++refused;
    spdlog::debug("asset '{}': {} {} refused: {}", name, kind, number, check.problem);
    publisher_.report_refusal(name, snapshot, time_ns, check.problem);
    return false;
  }
  log_adjustments(name, a);
  return true;
}

void EstimatorProcessing::feed_condition(const causal_twin::ConditionVector& in, GroupState& a) {
  const std::string& name = in.asset_group();
  if (a.channel_names.empty()) {
    a.channel_names.assign(in.channel_names().begin(), in.channel_names().end());
    a.pipeline.set_channel_names(a.channel_names);
  }
  if (a.feature.empty()) a.feature = in.feature();
  out_.clear();
  const auto started = std::chrono::steady_clock::now();
  pipeline::FrameCheck check;
  try {
    check = a.pipeline.feed_condition(dds::values_of(in), in.snapshot_index(), in.discontinuity(), in.time_ns(), out_);
  } catch (const std::exception& e) {
    fail(name, a, e, in.snapshot_index(), in.time_ns());
    return;
  }
  if (!accepted(name, a, check, a.refused_conditions, "condition vector", in.snapshot_index(), in.snapshot_index(),
                in.time_ns())) {
    return;
  }
  ++a.conditions_in;
  a.last_time_ns = in.time_ns();
  // The accepted vector goes on to the estimator's own topic: the one stream of condition vectors that the
  // recommender, the recorder and the HMI read, whatever the source.
  pipeline::ConditionSample accepted;
  accepted.snapshot_index = in.snapshot_index();
  accepted.time_ns = in.time_ns();
  accepted.values = dds::values_of(in);
  accepted.discontinuity = in.discontinuity();
  out_.conditions.insert(out_.conditions.begin(), std::move(accepted));
  publisher_.publish_quality(name, a, out_, in.snapshot_index(), in.time_ns(), true);
  publisher_.publish(name, a, out_, true, nullptr);
  if (!publisher_.standing_by()) log_learned(name, a);
  a.condition_seconds->observe(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
}

void EstimatorProcessing::fail(const std::string& name, GroupState& a, const std::exception& e,
                               std::uint64_t snapshot, std::int64_t time_ns) {
  // A fault in one asset group's estimation must not end the others: this group stops, loudly.
  a.refused = std::string("estimation failed: ") + e.what();
  spdlog::error("asset '{}': {}; its input is refused from now on (counted)", name, a.refused);
  ++a.refused_inputs;
  publisher_.report_refusal(name, snapshot, time_ns, a.refused);
}

void EstimatorProcessing::finish() {
  for (auto& [name, a] : groups_) {
    if (!a.refused.empty()) continue;
    publisher_.checkpoint_at_exit(name, a);
    out_.clear();
    try {
      a.pipeline.finish(out_);
      publisher_.publish(name, a, out_, false, nullptr);
      if (!publisher_.standing_by()) log_learned(name, a);
    } catch (const std::exception& e) {
      // A shutdown must never crash (SIGTERM included): this group's flush is lost, said and counted.
      a.refused = std::string("flushing at exit failed: ") + e.what();
      ++a.refused_inputs;
      spdlog::error("asset '{}': {}", name, a.refused);
    }
  }
}

void EstimatorProcessing::log_adjustments(const std::string& name, GroupState& a) {
  if (a.adjustments_logged) return;
  a.adjustments_logged = true;
  for (const auto& adj : a.pipeline.calibration_adjustments()) {
    spdlog::info("asset '{}': {} channels: {} calibration window {} samples instead of the configured {} (the model "
                 "needs {})",
                 name, a.pipeline.channels(), adj.window, adj.used, adj.configured, adj.rule);
  }
}

void EstimatorProcessing::log_learned(const std::string& name, GroupState& a) {
  log_structure(name, a, "sample level", a.pipeline.sample_structure(), a.sample_structure_logged);
  log_structure(name, a, "condition level", a.pipeline.condition_structure(), a.condition_structure_logged);
  const auto* s = a.pipeline.sample_stream();
  if (s != nullptr && s->calibrated() && !a.tuning_logged) {
    a.tuning_logged = true;
    for (std::size_t k = 0; k < s->noise().size(); ++k) {
      spdlog::info("{} sample level, outcome {}: q = {:.3g}, r = {:.3g}{}", name, a.channel_names.at(k),
                   s->noise()[k].q, s->noise()[k].r,
                   s->tuning().empty() ? " (fixed)" : " (tuned: " + s->tuning()[k].message + ")");
    }
  }
}

void EstimatorProcessing::log_startup_done(const std::string& name, GroupState& a) {
  const auto* s = a.pipeline.sample_stream();
  if (s == nullptr || !s->calibrated() || s->replay_pending() > 0) return;
  a.startup_logged = true;
  // Machine-readable (deploy/bench_scale.sh): frames= counts every group's frames fed so far, this one included.
  spdlog::info("summary startup_done group={} group_frames={} {}", name, a.frames, process_cpu_summary(frames_fed_));
}

void EstimatorProcessing::log_structure(const std::string& name, const GroupState& a, const char* level,
                                        const pipeline::LearnedStructure* learned, bool& logged) const {
  if (learned == nullptr || !learned->ready || learned->samples == 0 || logged) return;
  logged = true;
  const auto& names = a.channel_names;
  if (learned->centre.size() > 0) {
    std::string text;
    for (Eigen::Index j = 0; j < learned->centre.size(); ++j) {
      text += fmt::format("{}{}={:.4g}", j ? " " : "", names.at(static_cast<std::size_t>(j)), learned->centre[j]);
    }
    spdlog::info("{} {}: inputs centred on the mean of the first {} samples: {}", name, level, learned->samples, text);
  }
  if (!learned->order.empty()) {
    std::string order, links;
    for (std::size_t p = 0; p < learned->order.size(); ++p) {
      order += (p ? " < " : "") + names.at(static_cast<std::size_t>(learned->order[p]));
    }
    const auto& mask = learned->instantaneous_allowed;
    for (std::size_t k = 0; k < mask.size(); ++k) {
      for (std::size_t j = 0; j < mask[k].size(); ++j) {
        if (j == k || !mask[k][j]) continue;
        links += fmt::format("{}{} -> {} (B0 {:+.3f})", links.empty() ? "" : ", ", names.at(j), names.at(k),
                             learned->b0(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j)));
      }
    }
    spdlog::info("{} {}: causal order learned by VAR-LiNGAM on {} samples: {}; instantaneous links: {}", name, level,
                 learned->samples, order, links.empty() ? "none" : links);
  }
  if (!learned->order_summary.empty()) {
    spdlog::log(learned->order_source == "untrusted" ? spdlog::level::warn : spdlog::level::info,
                "{} {}: causal order {}: {}", name, level, learned->order_source, learned->order_summary);
  }
  if (!learned->problem.empty()) spdlog::warn("{} {}: {}", name, level, learned->problem);
}

}  // namespace causal::estimator
