// One asset group's causal factors on one time scale, fed sample by sample, reported every N samples.
//
// Wraps the Kalman filter (and optionally the fixed-lag smoother) with what a streaming service needs:
//  * automatic noise: the first `calibration_samples` samples are buffered, q and r are tuned on them by
//    maximising the innovation likelihood (causal/estimation/noise_tuning.hpp), then the buffer is replayed through
//    the filter, so no sample is lost to calibration;
//  * a publication cadence: every `publish_every` samples one report per outcome with the factors, their
//    standard deviations and the innovation statistics since the previous report; the fixed-lag smoother
//    reports the same sample indices once its lag has passed;
//  * per-sample times and source indices, so each report carries the UTC time and the index (as numbered by
//    the source: the sensor's sample index, or the snapshot index at condition level) of the sample it
//    refers to; a restart or a lost frame does not shift them;
//  * checkpoints: save() / restore() (state_archive.hpp) let a restarted service continue bit for bit.
#pragma once

#include "causal/estimation/fixed_lag_smoother.hpp"
#include "causal/estimation/innovation_stats.hpp"
#include "causal/estimation/noise_params.hpp"
#include "causal/estimation/noise_tuning.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"
#include "causal/estimation/svar_layout.hpp"

#include "causal/pipeline/calibration_window.hpp"
#include "causal/pipeline/tuning_worker.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <deque>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::pipeline {

enum class EstimateKind { Filter, FixedLag };

struct NoiseSetting {
  bool automatic = false;            // tune q and r per outcome on a calibration window
  estimation::NoiseParams fixed;                 // used as is when !automatic; fixed.p0 is also the tuning's p0
  std::size_t calibration_samples = 2048;
  // Where the automatic tuning runs: null = on the feeding thread, at the sample that fills the window;
  // else on this worker, while the stream keeps buffering what it is fed (polled at each feed; finish() waits).
  // The reports are the same either way (tuned on the same first calibration_samples samples, then every
  // buffered sample replayed in order); with a worker they come out at a later feed. Not saved in checkpoints.
  // The buffer is bounded: a stream holding kWorkerBufferFactor x calibration_samples samples waits for its
  // tuning (memory per group stays bounded however long the worker's queue is, e.g. many groups joining at once).
  std::shared_ptr<TuningWorker> worker;
  static constexpr std::size_t kWorkerBufferFactor = 8;
  // With a worker, the buffered window is replayed a share at a time once the tuning is in: each feed replays
  // what it brings plus calibration_samples / kReplayShare more, so a group whose tuning arrives adds at most
  // that much filter work to one feed instead of its whole window (the other groups' frames wait for it on the
  // same thread). Samples fed meanwhile queue behind the window: the filter sees them in the same order.
  static constexpr std::size_t kReplayShare = 4;
};

struct FactorStreamParams {
  estimation::ModelSpec model;
  NoiseSetting noise;
  std::size_t publish_every = 1024;  // samples between reports (>= 1)
  int fixed_lag = 0;                 // > 0: also report the fixed-lag smoother with this lag
};

struct FactorReport {
  EstimateKind kind = EstimateKind::Filter;
  int outcome = 0;                   // 0-based k
  std::uint64_t sample_index = 0;    // source index of the sample the estimate refers to (feed's first_index + row)
  std::int64_t time_ns = 0;          // its UTC time
  Eigen::VectorXd factors;           // outcome k's factors (layout order)
  Eigen::VectorXd std_devs;
  Eigen::MatrixXd covariance;        // P_k (filter reports); empty for fixed-lag reports
  std::uint64_t innovation_count = 0;  // updates since the previous report
  double innovation_mean = 0.0;
  double nis_mean = 0.0;
  double last_innovation = 0.0;
  double last_innovation_variance = 0.0;
  std::uint64_t rejected = 0;        // cumulative non-finite samples
  double q = 0.0, r = 0.0;
  // std_devs entries that are 0 (a variance <= 0 from rounding, clamped) or not finite: this outcome's filter
  // lost precision (ill-scaled input) and its factors should not be trusted. 0 normally.
  std::uint32_t degenerate_std = 0;
};

// Checkpoint helpers shared by the streams: write the parameters, and check on restore that an object is
// built with the same ones (StateError naming the first that differs, e.g. "checkpoint has publish_every 1024,
// this factor stream has 512"). The model spec is checked separately (expect_same_model).
void save_stream_params(estimation::StateWriter& w, const FactorStreamParams& params);
void expect_same_stream_params(estimation::StateReader& r, const FactorStreamParams& params, const std::string& owner);

class FactorStream {
 public:
  explicit FactorStream(FactorStreamParams params);  // throws std::invalid_argument for invalid params
  // Automatic noise needs clearly more usable samples than factors per outcome: 10 x factors + 10.
  static std::size_t minimum_noise_calibration_samples(const estimation::ModelSpec& model);

  // Feeds the rows of an N x G block; row 0 has the source index first_index (row i: first_index + i) and
  // is at first_time_ns, rows are period_ns apart, `discontinuity` applies to row 0. Reports are appended
  // to `out`. The publication cadence counts fed samples (every publish_every-th), not source indices.
  void feed(const Eigen::Ref<const RowMajorMatrix>& block, std::uint64_t first_index, bool discontinuity,
            std::int64_t first_time_ns, double period_ns, std::vector<FactorReport>& out);
  // End of stream: calibrates on what was buffered (if still calibrating) and flushes the smoother.
  void finish(std::vector<FactorReport>& out);

  const estimation::SvarLayout& layout() const { return layout_; }
  bool calibrated() const { return smoother_ != nullptr; }
  std::size_t replay_pending() const { return smoother_ ? window_.size() : 0; }  // buffered samples not yet replayed
  bool tuning_in_background() const { return tuning_job_.valid(); }  // submitted to the worker, not yet taken
  const std::vector<estimation::NoiseParams>& noise() const { return noise_; }
  const std::vector<estimation::NoiseTuningResult>& tuning() const { return tuning_; }
  // Data problems the stream worked around (e.g. automatic noise failed for an outcome and the configured
  // noise runs instead), one human-readable line each; the service decides how to log them.
  const std::vector<std::string>& warnings() const { return warnings_; }
  estimation::FilterCounters counters() const;
  std::uint64_t samples_seen() const { return next_index_; }  // samples through the filter (not buffered ones)

  // Checkpoint (state_archive.hpp), section "factor_stream". Saved: the parameters (model spec, noise
  // setting, publish_every, fixed_lag: restore throws StateError when this stream was built with others),
  // the noise in use and the tuning results, the smoother with its filter (once calibrated), the innovation
  // statistics since the last report, the calibration buffer (samples, discontinuities, times, source
  // indices), the filter reports waiting for their fixed-lag twins, and the sample counters. Feeding the
  // rest of a stream after restore() gives bit for bit the reports of an uninterrupted run. On StateError
  // (other parameters, damaged checkpoint) the stream is left unchanged.
  void save(estimation::StateWriter& w) const;
  void restore(estimation::StateReader& r);

 private:
  struct Pending {  // a filter report waiting for its fixed-lag twin
    std::uint64_t index;         // fed-sample count of the report (what the smoother releases)
    std::int64_t time_ns;
    std::vector<FactorReport> filter_reports;  // carry the source index
  };
  void calibrate(std::vector<FactorReport>& out);  // tunes on this thread (or waits for the worker), replays
  void start_tuning();                             // submits the tuning of the window's first samples
  void poll_tuning(std::vector<FactorReport>& out);  // the worker's result, when ready: install and replay
  void install_tuning(std::vector<estimation::NoiseTuningResult> tuning, std::vector<FactorReport>& out);
  void replay(std::size_t fed_rows, std::vector<FactorReport>& out);  // the window's next share (all without a worker)
  void process(const double* y, bool discontinuity, std::int64_t time_ns, std::uint64_t source_index,
               std::vector<FactorReport>& out);
  void emit_filter(std::uint64_t index, std::uint64_t source_index, std::int64_t time_ns,
                   std::vector<FactorReport>& out);
  void emit_smoothed(const estimation::SmoothedSample& s, std::vector<FactorReport>& out);
  FactorReport make_report(EstimateKind kind, int k, std::uint64_t index, std::int64_t time_ns,
                           const Eigen::VectorXd& all_factors, const Eigen::VectorXd& all_std) const;

  FactorStreamParams params_;
  estimation::SvarLayout layout_;
  int g_;
  std::vector<estimation::NoiseParams> noise_;
  std::vector<estimation::NoiseTuningResult> tuning_;
  std::vector<std::string> warnings_;
  std::unique_ptr<estimation::FixedLagSmoother> smoother_;  // lag 0 when only the filter is wanted
  estimation::InnovationStats stats_;
  CalibrationWindow window_;  // automatic noise only; grows past calibration_samples while the worker tunes
  std::future<std::vector<estimation::NoiseTuningResult>> tuning_job_;  // the worker's tuning (valid while submitted)
  std::deque<Pending> pending_;
  std::uint64_t next_index_ = 0;      // index of the next sample processed by the filter
  std::uint64_t buffered_index_ = 0;  // samples seen including the calibration buffer
  std::size_t since_report_ = 0;
  Eigen::VectorXd all_factors_, all_std_;
};

}  // namespace causal::pipeline
