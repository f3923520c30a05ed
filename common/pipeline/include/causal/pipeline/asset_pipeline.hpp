// Everything causal-estimator computes for one asset group: sample-level factors from raw frames,
// condition vectors from raw frames, and condition-level factors from those (or from condition vectors
// that arrive ready-made, e.g. replayed feature tables).
#pragma once

#include "causal/pipeline/condition_stream.hpp"
#include "causal/pipeline/factor_stream.hpp"
#include "causal/pipeline/input_screen.hpp"
#include "causal/pipeline/structured_factor_stream.hpp"

#include <memory>
#include <optional>
#include <string>

namespace causal::pipeline {

struct AssetPipelineParams {
  bool sample_level = true;
  FactorStreamParams sample;          // model.channels is set from the data
  StructureSetting sample_structure;  // centring / learned causal order (structured_factor_stream.hpp)
  // Optional configured causal graph of the instantaneous links, e.g. "bearing2 -> bearing1, 3 -> 1"
  // (channel names or 1-based numbers). Empty: every instantaneous link is estimated. Otherwise only the
  // listed links are; lagged links are unaffected. Must be acyclic: with instantaneous links running both
  // ways the per-outcome regressions do not form one identified structural model (common/analysis).
  std::string sample_graph;
  std::string condition_graph;
  bool condition_level = true;
  ConditionStreamParams condition;
  FactorStreamParams condition_model; // model.channels is set from the data
  StructureSetting condition_structure;
  // Input screens (input_screen.hpp): every raw frame row and every ready-made condition vector is screened
  // per channel before any stream sees it.
  InputScreenParams frame_screen = InputScreenParams::for_samples();
  InputScreenParams condition_screen = InputScreenParams::for_conditions();
};

struct PipelineOutput {
  std::vector<FactorReport> sample_reports;
  std::vector<FactorReport> condition_reports;
  std::vector<ConditionSample> conditions;  // computed here from raw frames (to publish)
  std::vector<QualityEvent> quality_events;  // input screen decisions (bad values, quarantine, recovery)
  void clear() {
    sample_reports.clear();
    condition_reports.clear();
    conditions.clear();
    quality_events.clear();
  }
};

struct FrameCheck {
  bool ok = true;
  std::string problem;
};

class AssetPipeline {
 public:
  explicit AssetPipeline(AssetPipelineParams params);
  // Names used to resolve the configured graphs; call before the first feed (else 1-based numbers only).
  void set_channel_names(std::vector<std::string> names) { channel_names_ = std::move(names); }

  // A raw frame: rows N x G (sample-major), `gap` = frames were lost before this one. The first frame fixes
  // G; a frame with another channel count is refused (FrameCheck.ok = false) and nothing is fed.
  FrameCheck feed_frame(const Eigen::Ref<const RowMajorMatrix>& rows, bool discontinuity, bool end_of_segment,
                        bool gap, std::int64_t first_time_ns, double sample_rate_hz, PipelineOutput& out);
  // A ready-made condition vector (feature values per channel, e.g. from a replayed feature table).
  FrameCheck feed_condition(const Eigen::VectorXd& values, bool discontinuity, std::int64_t time_ns,
                            PipelineOutput& out);
  void finish(PipelineOutput& out);

  int channels() const { return channels_; }
  // The running filters; null before the first frame and while a structure calibration window fills.
  const FactorStream* sample_stream() const { return sample_ ? sample_->stream() : nullptr; }
  const FactorStream* condition_stream() const { return condition_model_ ? condition_model_->stream() : nullptr; }
  // What the structure calibration learned (null before the first frame or when the level is disabled).
  const LearnedStructure* sample_structure() const { return sample_ ? &sample_->structure() : nullptr; }
  const LearnedStructure* condition_structure() const {
    return condition_model_ ? &condition_model_->structure() : nullptr;
  }
  // Per-channel input screen counters (Sample: raw frame rows, Condition: ready-made condition vectors); empty
  // before the first frame or vector has fixed the channel count.
  const std::vector<ChannelQualityCounters>& quality_counters(ScreenLevel level = ScreenLevel::Sample) const;
  std::uint64_t dropped_condition_windows() const { return conditions_ ? conditions_->dropped_windows() : 0; }

 private:
  bool fix_channels(int g, FrameCheck& check);
  void feed_condition_model(const ConditionSample& s, PipelineOutput& out);

  AssetPipelineParams params_;
  std::vector<std::string> channel_names_;
  int channels_ = 0;
  std::unique_ptr<StructuredFactorStream> sample_;
  std::unique_ptr<ConditionStream> conditions_;
  std::unique_ptr<StructuredFactorStream> condition_model_;
  std::unique_ptr<InputScreen> frame_screen_, condition_screen_;
  RowMajorMatrix screened_rows_;  // the screened copy of the frame being fed
};

}  // namespace causal::pipeline
