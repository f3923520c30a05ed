#include "estimator_node.hpp"

#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

namespace causal::estimator {

namespace {
using Clock = std::chrono::steady_clock;
}

std::uint64_t shard_hash(const std::string& asset_group) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : asset_group) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

EstimatorNode::EstimatorNode(EstimatorOptions options, pipeline::AssetPipelineParams params)
    : options_(std::move(options)),
      params_(std::move(params)),
      participant_(dds::to_dds_settings(options_.dds, "causal-estimator")),
      frames_(participant_, dds::topics::kVibrationFrame, dds::profiles::kVibrationFrameReader),
      conditions_in_(participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorReader),
      factors_(participant_, dds::topics::kCausalFactors, dds::profiles::kCausalFactorsWriter),
      conditions_out_(participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorWriter) {
  loop_.attach(frames_.get());
  loop_.attach(conditions_in_.get());
}

bool EstimatorNode::mine(const std::string& asset_group) const {
  return options_.shard_count <= 1 ||
         shard_hash(asset_group) % static_cast<std::uint64_t>(options_.shard_count) ==
             static_cast<std::uint64_t>(options_.shard_index);
}

EstimatorNode::Asset& EstimatorNode::asset(const std::string& asset_group) {
  auto it = assets_.find(asset_group);
  if (it == assets_.end()) {
    it = assets_.emplace(asset_group, Asset(params_)).first;
    spdlog::info("new asset group '{}'", asset_group);
  }
  return it->second;
}

int EstimatorNode::run() {
  spdlog::info("causal-estimator on domain {} (shard {}/{}), waiting for frames", participant_.domain_id(),
               options_.shard_index, options_.shard_count);
  if (options_.wait_subscribers > 0) {
    // Frames that arrive meanwhile wait in the reliable reader's history: nothing is lost.
    const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.wait_timeout_s * 1000.0));
    if (!factors_.wait_for_readers(static_cast<std::size_t>(options_.wait_subscribers), timeout, loop_.stop_flag())) {
      if (loop_.stopped()) return 0;
      spdlog::error("fewer than {} factor readers matched within {:.0f} s: is alarm-recommender running on domain {}?",
                    options_.wait_subscribers, options_.wait_timeout_s, participant_.domain_id());
      return 3;
    }
  }
  const auto started = Clock::now();
  auto last_data = started;
  bool any_data = false;
  while (loop_.wait(std::chrono::milliseconds(200))) {
    const std::size_t n = frames_.take_all([this](const auto& f, const auto&) { on_frame(f); }) +
                          conditions_in_.take_all([this](const auto& c, const auto& info) {
                            // Our own condition vectors come back to us through the shared topic: skip them.
                            if (info.sample_identity.writer_guid() == conditions_out_.get()->guid()) return;
                            on_condition(c);
                          });
    const auto now = Clock::now();
    if (n > 0) {
      last_data = now;
      any_data = true;
    }
    // Idle exit only once every source has left the domain: a source that is merely blocked (by a slow
    // reader elsewhere) or paced must not end the run. Our own condition writer also matches our reader.
    const std::size_t sources = frames_.matched_writers() + conditions_in_.matched_writers() - 1;
    if (options_.idle_exit_s > 0 && any_data && sources == 0 &&
        std::chrono::duration<double>(now - last_data).count() > options_.idle_exit_s) {
      spdlog::info("all sources gone and no data for {:.1f} s: finishing", options_.idle_exit_s);
      break;
    }
    if (options_.max_runtime_s > 0 && std::chrono::duration<double>(now - started).count() > options_.max_runtime_s) {
      spdlog::warn("max runtime {:.0f} s reached: finishing", options_.max_runtime_s);
      break;
    }
  }
  finish_all();
  return 0;
}

void EstimatorNode::on_frame(const causal_twin::VibrationFrame& frame) {
  if (!mine(frame.asset_group())) {
    ++foreign_frames_;
    return;
  }
  if (const std::string problem = dds::validate_frame(frame); !problem.empty()) {
    ++invalid_msgs_;
    spdlog::warn("asset '{}': frame {} refused: {}", frame.asset_group(), frame.sequence_number(), problem);
    return;
  }
  Asset& a = asset(frame.asset_group());
  // Sequence numbers run 0, 1, 2, ... per publisher; a jump means frames were lost on the way, a return to
  // 0 a restarted publisher (its first frame is flagged as a discontinuity anyway).
  bool gap = false;
  if (a.last_sequence && frame.sequence_number() != *a.last_sequence + 1 && frame.sequence_number() != 0) {
    gap = true;
    a.lost_frames += frame.sequence_number() > *a.last_sequence ? frame.sequence_number() - *a.last_sequence - 1 : 0;
    spdlog::warn("asset '{}': frames {}..{} missing; lags restart", frame.asset_group(), *a.last_sequence + 1,
                 frame.sequence_number() - 1);
  }
  a.last_sequence = frame.sequence_number();
  if (a.channel_names.empty()) {
    a.channel_names = dds::channel_names(frame);
    a.pipeline.set_channel_names(a.channel_names);
  }
  out_.clear();
  // Indices come from the source, so reports keep them across a restart or a lost frame.
  const std::uint64_t snapshot_index = 0;  // TODO(lead): frame.snapshot_index() once the IDL carries it
  const auto check = a.pipeline.feed_frame(dds::samples_view(frame), frame.first_sample_index(), snapshot_index,
                                           frame.discontinuity(), frame.end_of_segment(), gap,
                                           frame.first_sample_time_ns(), frame.sample_rate_hz(), out_);
  if (!check.ok) {
    ++a.refused_frames;
    spdlog::warn("asset '{}': frame {} refused: {}", frame.asset_group(), frame.sequence_number(), check.problem);
    return;
  }
  ++a.frames;
  if (a.feature.empty()) a.feature = io::to_string(params_.condition.feature);
  publish(frame.asset_group(), a);
}

void EstimatorNode::on_condition(const causal_twin::ConditionVector& in) {
  if (!mine(in.asset_group())) return;
  if (const std::string problem = dds::validate_condition_vector(in); !problem.empty()) {
    ++invalid_msgs_;
    spdlog::warn("asset '{}': condition vector {} refused: {}", in.asset_group(), in.snapshot_index(), problem);
    return;
  }
  Asset& a = asset(in.asset_group());
  if (a.channel_names.empty()) {
    a.channel_names.assign(in.channel_names().begin(), in.channel_names().end());
    a.pipeline.set_channel_names(a.channel_names);
  }
  if (a.feature.empty()) a.feature = in.feature();
  out_.clear();
  const auto check =
      a.pipeline.feed_condition(dds::values_of(in), in.snapshot_index(), in.discontinuity(), in.time_ns(), out_);
  if (!check.ok) {
    ++a.refused_frames;
    spdlog::warn("asset '{}': condition vector {} refused: {}", in.asset_group(), in.snapshot_index(), check.problem);
    return;
  }
  ++a.conditions_in;
  publish(in.asset_group(), a);
}

void EstimatorNode::log_condition_report(const std::string& name, const Asset& a, const pipeline::FactorReport& r) {
  const auto* stream = a.pipeline.condition_stream();
  std::string text;
  for (Eigen::Index i = 0; i < r.factors.size(); ++i) {
    text += fmt::format("{}{}={:+.3f}±{:.3f}", i ? " " : "", stream->layout().factor_name(r.outcome, static_cast<int>(i)),
                        r.factors[i], r.std_devs[i]);
  }
  spdlog::info("{} snapshot {} {} {} [{}] NIS {:.2f}: {}", name, r.sample_index, io::format_utc(r.time_ns),
               a.channel_names.at(static_cast<std::size_t>(r.outcome)),
               r.kind == pipeline::EstimateKind::Filter ? "filter" : "fixed-lag", r.nis_mean, text);
}

void EstimatorNode::log_structure(const std::string& name, const Asset& a, const char* level,
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
  if (!learned->problem.empty()) spdlog::warn("{} {}: {}", name, level, learned->problem);
}

void EstimatorNode::publish(const std::string& name, Asset& a) {
  const std::atomic<bool>& stop = loop_.stop_flag();
  for (const auto& c : out_.conditions) {
    dds::ConditionHeader h{name, a.feature, c.snapshot_index, c.time_ns, a.channel_names, c.discontinuity};
    dds::to_condition_vector(h, c.values, condition_msg_);
    conditions_out_.write(condition_msg_, stop);
  }
  auto send = [&](const std::vector<pipeline::FactorReport>& reports, const pipeline::FactorStream* stream,
                  causal_twin::TimeScale scale, std::uint64_t& counter) {
    if (reports.empty()) return;
    const dds::FactorContext ctx{name, scale, scale == causal_twin::CONDITION_LEVEL ? a.feature : "", &stream->layout(),
                                 a.channel_names};
    for (const auto& r : reports) {
      dds::to_causal_factors(ctx, r, factor_msg_);
      if (factors_.write(factor_msg_, stop) == dds::WriteResult::Ok) ++counter;
      if (scale == causal_twin::CONDITION_LEVEL) log_condition_report(name, a, r);
    }
  };
  send(out_.sample_reports, a.pipeline.sample_stream(), causal_twin::SAMPLE_LEVEL, a.sample_msgs);
  send(out_.condition_reports, a.pipeline.condition_stream(), causal_twin::CONDITION_LEVEL, a.condition_msgs);
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

void EstimatorNode::finish_all() {
  for (auto& [name, a] : assets_) {
    out_.clear();
    a.pipeline.finish(out_);
    publish(name, a);
    const auto* s = a.pipeline.sample_stream();
    spdlog::info("asset '{}': {} frames ({} lost, {} refused), {} condition vectors in, {} sample-level and {} "
                 "condition-level factor messages out, {} non-finite samples rejected",
                 name, a.frames, a.lost_frames, a.refused_frames, a.conditions_in, a.sample_msgs, a.condition_msgs,
                 s ? s->counters().rejected_non_finite : 0);
  }
  if (foreign_frames_ > 0) spdlog::info("{} frames of other shards ignored", foreign_frames_);
  if (invalid_msgs_ > 0) spdlog::warn("{} malformed messages refused", invalid_msgs_);
  if (!factors_.wait_for_acknowledgments(std::chrono::seconds(10))) {
    spdlog::warn("not every factor message was acknowledged within 10 s");
  }
  conditions_out_.wait_for_acknowledgments(std::chrono::seconds(10));
}

}  // namespace causal::estimator
