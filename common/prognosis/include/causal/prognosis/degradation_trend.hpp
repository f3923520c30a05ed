// Degradation trend of one channel: a local trend on the log level whose slope changes over time, Kalman-
// filtered in continuous time (hours from the data's time_ns: IMS snapshots are 10 min apart, other runs have
// multi-day gaps).
//
// Why this model: wear accelerates. The log level m(t) of a degrading bearing rises with a slope b(t) that
// itself grows (IMS test 2, bearing 1: ~0.01 log/h two days before the stop, ~0.13 log/h in the last two
// hours). A fixed-shape law fitted since onset lags that acceleration, and so does a slope that follows a
// plain random walk (it assumes the slope stays where it is): measured on the simulations, the forecasts of a
// local linear trend came late and their intervals missed (docs/prognosis.md). So the state carries the
// acceleration too, x = [m, b, a], with dm = b dt, db = a dt, da = sqrt(q) dW (a local quadratic trend, the
// integrated random walk one order up), discretised exactly over any step dt:
//   F = [1 dt dt^2/2; 0 1 dt; 0 0 1],
//   Q = q [dt^5/20 dt^4/8 dt^3/6; dt^4/8 dt^3/3 dt^2/2; dt^3/6 dt^2/2 dt] + q_level dt e1 e1^T
// (Bar-Shalom, Li, Kirubarajan 2001, "Estimation with Applications to Tracking and Navigation", sec. 6.2.3:
// the continuous Wiener-process acceleration model). Measurement: y = log(feature) = m + v, Var v = R.
//
// Robustness: R starts from the channel's baseline scale (the alarm engine's 1.4826 MAD of the log feature),
// is scaled up by a running mean of the clipped excess innovation energy (degradation makes a channel noisier
// than it was healthy), and a single innovation beyond huber_k standard deviations has bounded influence
// (Huber weight: its gain is scaled by huber_k / |z|). A discontinuity (recording gap, restart) adds level
// variance step_std^2, so a level step there is absorbed by the level, not read as a slope.
//
// Calibration: the trend checks its own forecasts against what came (calibration_lag_hours later) and keeps the
// running mean square of the standardised errors as an inflation >= 1 of its acceleration diffusion and of the
// forecast variance: on the simulations the truth came EARLIER than the intervals (the filter lagged wear whose
// acceleration itself grows), and a channel's own errors are the evidence of how much (docs/prognosis.md).
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::prognosis {

struct TrendParams {
  // q: spectral density of the acceleration random walk, (log level / h^2)^2 per hour. Chosen on the
  // simulations (docs/prognosis.md has the sensitivity table), not on IMS.
  double acceleration_diffusion = 1e-8;
  // Share of that diffusion carried into the forecast, folded to non-negative increments (wear does not
  // heal): 0 = the forecast's uncertainty is the posterior's only. See time_to_level.hpp.
  double forecast_diffusion = 1.0;
  double level_diffusion = 1e-6;          // (log level)^2 per hour: slow wander of the level itself
  double initial_slope_std = 0.02;        // prior std of the slope at the first observation, log level per hour
  double initial_acceleration_std = 1e-3; // prior std of the acceleration, log level per hour^2
  double min_noise_std = 0.005;     // floor of the measurement std (log units): a baseline scale of 0 is not a model
  double huber_k = 3.0;             // innovations beyond k sigma have bounded influence
  double noise_memory = 36.0;       // observations of the running noise scale (36 = 6 h at 10-min spacing)
  double step_std = 0.2;            // level std added at a discontinuity (re-levelling after a gap: +15-20 %)
  // Online calibration of the forecast from the channel's own past forecast errors: every calibration_lag_hours
  // the forecast made calibration_lag_hours ago is compared with the observation now, and the running mean
  // square of that standardised error (memory calibration_memory checks, each clipped at huber_k^2 times the
  // current value) becomes TrendState::inflation (never below 1): it scales the forecast's posterior
  // variance and the acceleration diffusion of both the filter and the forecast (the filter lagged accelerating
  // wear: let its acceleration change faster). 0 lag = off. Chosen on simulation seeds 1-20, judged on
  // seeds 101-120 and IMS (docs/prognosis.md).
  double calibration_lag_hours = 1.0;
  double calibration_memory = 8.0;
  void validate() const;            // throws std::invalid_argument naming the bad field
};

// Posterior of the trend at the time of the last observation.
struct TrendState {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  // [log level, slope per hour, acceleration per hour^2]
  Eigen::Matrix3d p = Eigen::Matrix3d::Zero();  // its covariance
  std::int64_t time_ns = 0;                     // time of the last observation
  // Forecast variance inflation (>= 1) from the calibration: the model's own past forecasts missed by this
  // many times their variance on this channel (adaptive variance inflation; Jazwinski 1970, ch. 8).
  double inflation = 1.0;
};

// Predicted log level s hours after the state's time: mean and variance, including the forecast diffusion
// folded to non-negative increments (time_to_level.hpp) and the inflation.
struct Forecast {
  double mean = 0.0, var = 0.0;
};
Forecast forecast(const TrendState& s, const TrendParams& trend, double hours);

class DegradationTrend {
 public:
  explicit DegradationTrend(TrendParams params = {});

  // One observation: log level y at time_ns, measurement std of the channel when healthy (log units).
  // Non-finite y or noise, and a time not after the previous one, are refused (false, counted).
  bool observe(std::int64_t time_ns, double log_level, double noise_std, bool discontinuity);

  bool started() const { return observations_ > 0; }
  const TrendState& state() const { return state_; }
  std::uint64_t observations() const { return observations_; }
  std::uint64_t refused() const { return refused_; }
  std::uint64_t downweighted() const { return downweighted_; }  // innovations beyond huber_k sigma
  double noise_scale() const { return noise_scale_; }           // current R / R_baseline
  std::uint64_t calibration_checks() const { return checks_; }  // forecast errors the inflation has seen
  const TrendParams& params() const { return params_; }

  // Checkpoint: every field, so a restored trend continues bit for bit (restore throws estimation::StateError).
  void save(estimation::StateWriter& out) const;
  static DegradationTrend restore(estimation::StateReader& in, const TrendParams& params);

 private:
  // The checkpoint's field lists (SaveFields / RestoreFields, state_fields.hpp): Self is const when saving.
  template <class IO, class Self>
  static void fields(IO io, Self& self);
  void predict(double dt_hours, bool discontinuity);
  void calibrate(double y, double r, bool discontinuity);

  TrendParams params_;
  TrendState state_;
  double noise_scale_ = 1.0;
  TrendState reference_;      // the posterior calibration_lag_hours ago, whose forecast is checked next
  double error_ms_ = 1.0;     // running mean square of the standardised forecast errors
  std::uint64_t checks_ = 0;
  std::uint64_t observations_ = 0, refused_ = 0, downweighted_ = 0;
};

}  // namespace causal::prognosis
