// Everything causal-estimator computes for one asset group: sample-level factors from raw frames,
// condition vectors from raw frames, and condition-level factors from those (or from condition vectors
// that arrive ready-made, e.g. replayed feature tables).
//
// Indices are the source's (one index everywhere): sample-level reports carry the sensor's sample index,
// condition vectors and condition-level reports the source's snapshot index, so a restart or a lost frame
// does not shift them. save() / restore() checkpoint the whole asset group (crash and restart safety).
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

// Channel-count rule: calibration windows are configured for the shipped 4-channel groups. The structure
// window is NOT raised with G: a window too short for one dense VAR-LiNGAM order over G channels
// (10 x G x (M + 1)) learns the order per block of neighbouring channels (structured_factor_stream.hpp,
// LearnedStructure::blocks), so "healthy" is learned on the same stretch of the run at any width and the
// level baselines downstream do not wait longer for a wider group. Windows are raised only below what one
// block or the noise model needs:
//   structure window (VAR-LiNGAM order):          max(configured, 10 x min(G, 2) x (M + 1))
//   automatic noise window (q, r by likelihood):  max(configured, 10 x factors per outcome + 10)
// (the minimums StructuredFactorStream and FactorStream enforce). A run that ends before its window is full
// learns on what it has (finish()); when that is too little, the configured model runs and
// LearnedStructure::problem says why. Nothing is refused for its channel count; each raised window is listed
// (calibration_adjustments).
struct CalibrationAdjustment {
  std::string window;      // "condition-level structure", "sample-level noise", ...
  std::size_t configured = 0;
  std::size_t used = 0;
  std::string rule;        // the minimum that applied, e.g. "10 x min(G, 2) x (M + 1) = 10 x 2 x 2"
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

// Where the input stood: the source's index of the last sample fed through feed_frame (the last row of the
// last frame) and the last snapshot index fed (a frame's snapshot_index or a feed_condition vector's).
// Saved in the checkpoint, so a restarted service can skip input it already processed.
struct SourceIndex {
  bool has_sample = false;
  std::uint64_t sample = 0;
  bool has_snapshot = false;
  std::uint64_t snapshot = 0;
};

class AssetPipeline {
 public:
  explicit AssetPipeline(AssetPipelineParams params);
  // Names used to resolve the configured graphs; call before the first feed (else 1-based numbers only).
  void set_channel_names(std::vector<std::string> names) { channel_names_ = std::move(names); }
  // The names set, or restored from a checkpoint (empty before either).
  const std::vector<std::string>& channel_names() const { return channel_names_; }

  // A raw frame: rows N x G (sample-major); first_sample_index = the source's index of row 0 in the asset
  // group's sample stream (sample-level reports carry first_sample_index + row); snapshot_index = the
  // source's snapshot (segment) the frame belongs to (condition vectors of its segment carry it; with
  // condition.window_samples > 0 they carry the window's first sample index / window_samples instead);
  // `gap` = frames were lost before this one. The first frame fixes G; a frame with another channel count
  // is refused (FrameCheck.ok = false) and nothing is fed.
  FrameCheck feed_frame(const Eigen::Ref<const RowMajorMatrix>& rows, std::uint64_t first_sample_index,
                        std::uint64_t snapshot_index, bool discontinuity, bool end_of_segment, bool gap,
                        std::int64_t first_time_ns, double sample_rate_hz, PipelineOutput& out);
  // A ready-made condition vector (feature values per channel, e.g. from a replayed feature table) with the
  // source's snapshot index, which its condition-level reports carry.
  FrameCheck feed_condition(const Eigen::VectorXd& values, std::uint64_t snapshot_index, bool discontinuity,
                            std::int64_t time_ns, PipelineOutput& out);
  void finish(PipelineOutput& out);

  int channels() const { return channels_; }
  // The calibration windows raised for this group's channel count (empty before the first input, or when the
  // configured windows suffice). See CalibrationAdjustment.
  const std::vector<CalibrationAdjustment>& calibration_adjustments() const { return adjustments_; }
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

  // The last source indices fed (see SourceIndex), and dedupe after a restart: true when the frame's rows
  // [first_sample_index, first_sample_index + rows) / the condition vector were fed before. Frames are fed
  // whole, so a re-sent frame lies either wholly before or wholly after the last sample fed. Assumes the
  // source's indices only grow: a restarted source that numbers from 0 again must not be deduplicated.
  const SourceIndex& last_source_index() const { return last_; }
  bool already_fed_frame(std::uint64_t first_sample_index, std::size_t rows) const {
    return rows > 0 && last_.has_sample && first_sample_index + rows - 1 <= last_.sample;
  }
  bool already_fed_condition(std::uint64_t snapshot_index) const {
    return last_.has_snapshot && snapshot_index <= last_.snapshot;
  }

  // Checkpoint (causal/estimation/state_archive.hpp), section "asset_pipeline". Saved: which levels run and the
  // configured graphs, the channel count and names, the last source indices, and every stream's state
  // (StructuredFactorStream::save for both levels, ConditionStream::save). restore() takes the channel
  // count and names from the checkpoint, rebuilds the streams from this pipeline's params (resolving the
  // graphs as feed_frame would), restores them, and only then replaces the current state: on StateError
  // (another channel count, e.g. "checkpoint has 4 channels, this asset group has 8", other parameters, a
  // damaged checkpoint) the pipeline is unchanged. Feeding the rest of the input after save -> restore
  // into a fresh pipeline gives bit for bit the output of an uninterrupted run.
  void save(estimation::StateWriter& w) const;
  void restore(estimation::StateReader& r);

 private:
  struct Streams {
    std::unique_ptr<StructuredFactorStream> sample;
    std::unique_ptr<ConditionStream> conditions;
    std::unique_ptr<StructuredFactorStream> condition_model;
    std::vector<CalibrationAdjustment> adjustments;
  };
  // The streams for G = g channels from params_ (graphs resolved with channel_names_); throws
  // std::invalid_argument when the configured model does not fit.
  Streams build_streams(int g) const;
  // Takes the streams and builds fresh input screens for g channels.
  void install(Streams s, int g);
  bool fix_channels(int g, FrameCheck& check);
  void feed_condition_model(const ConditionSample& s, PipelineOutput& out);

  AssetPipelineParams params_;
  std::vector<std::string> channel_names_;
  int channels_ = 0;
  std::vector<CalibrationAdjustment> adjustments_;
  std::unique_ptr<StructuredFactorStream> sample_;
  std::unique_ptr<ConditionStream> conditions_;
  std::unique_ptr<StructuredFactorStream> condition_model_;
  std::unique_ptr<InputScreen> frame_screen_, condition_screen_;
  RowMajorMatrix screened_rows_;  // the screened copy of the frame being fed
  SourceIndex last_;
};

}  // namespace causal::pipeline
