// Scale-invariant estimation: every channel is divided by a robust scale s_j learned on the calibration
// window, the factors are estimated on the standardised data and reported in the user's units.
//
// Why: the random-walk prior (q I, p0 I) is isotropic over an outcome's factors and r is absolute, so on raw
// data a channel in other units (x1e6, x1e-9) gets a prior that is far too tight or far too loose, and the
// same physics gives different factors (measured: factor RMSE 0.24 instead of 0.038 with one channel x1e6).
// On standardised data the problem does not depend on the units at all.
//
// Units: with y_j = s_j z_j, the structural equation y_k = sum_j x_kj y_j + e_k becomes
// z_k = sum_j (x_kj s_j / s_k) z_j + e_k / s_k, so the factor estimated on z converts back as
//   x_kj = z-factor * s_k / s_j       (lagged factors alike; standard deviations alike, s > 0),
// innovations as e_k = s_k e_z and their variances as s_k^2 S_z. Noise parameters (given or tuned) are in
// standardised units: q per sample for a factor between unit-scale channels, r as a share of s_k^2.
//
// Refusals (status, never a throw for data): a channel that is constant over the calibration window (dead,
// stuck, or varying only at rounding level) carries no information and would make its factors
// unidentifiable; a factor output that is not finite names the factor, its outcome channel and the row.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "causal/estimation/batch_estimation.hpp"
#include "causal/estimation/noise_params.hpp"
#include "causal/estimation/noise_tuning.hpp"
#include "causal/estimation/svar_layout.hpp"

namespace causal::estimation {

enum class ScaleStatus {
  Ok,
  ConstantChannel,  // zero spread over the window (all zeros, stuck value, or spread < 1e-12 of its level)
  NoFiniteValues,   // not one finite value in the window
  OutOfRange        // scale not a normal double far from overflow (|y| around 1e-290 or 1e290)
};

const char* to_string(ScaleStatus status);

struct ChannelScales {
  std::vector<double> scale;           // s_j > 0 per channel (1 where the channel was refused)
  std::vector<ScaleStatus> status;     // per channel
  bool ok() const;                     // every channel Ok
  int first_refused() const;           // first channel that is not Ok, -1 if none
};

// Robust scale of each column of `window` (N x G) over its finite values: s_j = median(|y_j|) / 0.67449
// (equals the standard deviation for zero-mean Gaussian data; taken about 0 because the model has no
// intercept), or the root mean square when more than half the values are 0. A channel is constant when its
// standard deviation about its mean is 0 or below 1e-12 of its mean absolute value.
ChannelScales robust_channel_scales(const Eigen::MatrixXd& window);

enum class EstimatorKind { Filter, FixedLag, Rts };

struct StandardisedOptions {
  EstimatorKind estimator = EstimatorKind::Rts;
  int lag = 50;                      // fixed-lag smoother lag L
  bool standardise = true;           // false: estimate in the data's units (scales all 1), checks still made
  NoiseParams noise;                 // used unless auto_noise; standardised units when standardise
  bool auto_noise = false;           // tune q, r per outcome on the calibration window (p0 from tuning.p0)
  Eigen::Index calibration_samples = 0;  // first rows used for the scales and tuning; 0 = all
  NoiseTuningOptions tuning;
  BatchOutput output;                // decimation of the stored estimates (the estimates are the full run's)
};

enum class EstimationStatus {
  Ok,
  ConstantChannel,   // a channel is constant over the calibration window: refused (channel set)
  UnusableChannel,   // a channel has no finite value or an absurd scale in the window (channel set)
  TuningFailed,      // --auto-noise could not tune an outcome (channel set, message from tune_noise)
  NonFiniteOutput    // an estimate or standard deviation is not finite (channel = outcome, row, factor set)
};

const char* to_string(EstimationStatus status);

struct StandardisedRun {
  EstimationStatus status = EstimationStatus::Ok;
  std::string message;               // what went wrong, naming channel (1-based and by name) and row
  int channel = -1;                  // 0-based channel the status is about, -1 if none
  Eigen::Index row = -1;             // 0-based sample (data row) of a NonFiniteOutput
  std::string factor;                // factor name of a NonFiniteOutput
  ChannelScales scales;
  std::vector<NoiseParams> noise;    // per outcome, standardised units, as used
  std::vector<NoiseTuningResult> tuning;  // per outcome when auto_noise
  EstimationRun run;                 // in the user's units; only filled when status == Ok
};

// Runs the chosen estimator on samples (N x G, discontinuity empty or N flags) as described above.
// channel_names (empty, or G names) only make the messages readable. Throws std::invalid_argument for bad
// shapes or options (as the batch estimators do); data problems come back as a status.
StandardisedRun estimate_standardised(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                                      const std::vector<bool>& discontinuity, const StandardisedOptions& options,
                                      const std::vector<std::string>& channel_names = {});

// Converts an EstimationRun made on samples divided by `scale` into the user's units (see the header text).
void to_user_units(const SvarLayout& layout, const std::vector<double>& scale, EstimationRun& run);

}  // namespace causal::estimation
