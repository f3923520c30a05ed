// Condition level: one vector of per-channel condition features per contiguous segment (an IMS snapshot)
// or per fixed window of samples (a continuous sensor), computed from raw frames.
#pragma once

#include "causal/io/condition_features.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::pipeline {

struct ConditionStreamParams {
  io::ConditionFeature feature = io::ConditionFeature::Rms;
  // Model the log of the feature: vibration features are positive and change multiplicatively, so log
  // turns a fault that doubles RMS into the same step at any operating level; factors become elasticities.
  bool log_transform = true;
  std::size_t window_samples = 0;      // close a window after this many samples (0 = only at segment ends)
  std::size_t min_samples = 256;       // a shorter segment is dropped (too few samples for kurtosis/peak)
};

struct ConditionSample {
  // The source's index of this vector: the snapshot (segment) index the source gave its frames, or, when
  // windows are closed by sample count (window_samples > 0, a continuous sensor), the source index of the
  // window's first sample / window_samples. A restart or a dropped window does not shift it. (By sample
  // count the index is unique while windows stay aligned to the source's sample grid; a discontinuity in
  // the middle of a window starts a shifted one that can share its index with the next.)
  std::uint64_t snapshot_index = 0;
  std::int64_t time_ns = 0;            // time of the segment's first sample
  Eigen::VectorXd values;              // feature per channel
  Eigen::VectorXd model_input;         // what the condition-level filter sees (log(values) or values)
  std::size_t samples = 0;             // samples the features were computed from
  bool discontinuity = false;          // the condition-level model must restart its lags here
};

// The model input for a condition vector: log(values) when log_transform (non-positive values become NaN,
// which the filter rejects and counts), values otherwise.
Eigen::VectorXd condition_model_input(const Eigen::VectorXd& values, bool log_transform);

class ConditionStream {
 public:
  ConditionStream(ConditionStreamParams params, int channels);
  // rows: N x G sample-major samples, period_ns apart; row 0 has the source's sample index
  // first_sample_index and belongs to the source's snapshot `snapshot_index` (see ConditionSample). Appends
  // finished condition samples to `out`. With window_samples > 0 a frame is split so that every window
  // holds exactly window_samples samples.
  void feed(const double* rows, std::size_t n, std::uint64_t first_sample_index, std::uint64_t snapshot_index,
            bool discontinuity, bool end_of_segment, std::int64_t first_time_ns, double period_ns,
            std::vector<ConditionSample>& out);
  // A gap in the frame sequence (lost frames): the open window is discarded (features of a partial
  // snapshot would be biased) and the next vector restarts the condition-level lags.
  void drop_open_window();
  std::uint64_t dropped_windows() const { return dropped_; }
  std::uint64_t produced() const { return produced_; }  // condition vectors produced so far

  // Checkpoint (state_archive.hpp), section "condition_stream". Saved: the parameters and channel count
  // (restore throws StateError when this stream was built with others, leaving it unchanged), the open
  // window (accumulated moments, start time, source indices, rows fed), whether the next vector restarts
  // the lags, and the produced / dropped counters: a window cut by a restart gives the same vector.
  void save(estimation::StateWriter& w) const;
  void restore(estimation::StateReader& r);

 private:
  // The checkpoint's field list after the parameter checks (SaveFields / RestoreFields, state_fields.hpp).
  template <class IO, class Self>
  static void fields(IO io, Self& self);
  void close(std::vector<ConditionSample>& out);

  ConditionStreamParams params_;
  int channels_;
  io::ConditionAccumulator acc_;
  std::int64_t window_time_ns_ = 0;
  std::uint64_t window_first_sample_ = 0;  // source index of the open window's first sample
  std::uint64_t window_snapshot_ = 0;      // source snapshot index of the frame that opened it
  bool window_open_ = false;
  std::size_t fed_in_window_ = 0;  // rows fed into the open window (the accumulator counts accepted ones)
  bool next_discontinuity_ = true;
  std::uint64_t produced_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace causal::pipeline
