#include "causal/prognosis/degradation_trend.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace causal::prognosis {

namespace {

constexpr const char* kTag = "prognosis_degradation_trend";
constexpr std::uint32_t kVersion = 2;  // 2: forecast calibration (reference state, error mean square)
constexpr double kNsPerHour = 3.6e12;

void require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("TrendParams.") + field + " " + what);
}

}  // namespace

void TrendParams::validate() const {
  require(std::isfinite(acceleration_diffusion) && acceleration_diffusion >= 0, "acceleration_diffusion",
          "must be finite and >= 0");
  require(std::isfinite(forecast_diffusion) && forecast_diffusion >= 0, "forecast_diffusion",
          "must be finite and >= 0");
  require(std::isfinite(initial_acceleration_std) && initial_acceleration_std > 0, "initial_acceleration_std",
          "must be finite and > 0");
  require(std::isfinite(level_diffusion) && level_diffusion >= 0, "level_diffusion", "must be finite and >= 0");
  require(std::isfinite(initial_slope_std) && initial_slope_std > 0, "initial_slope_std", "must be finite and > 0");
  require(std::isfinite(min_noise_std) && min_noise_std > 0, "min_noise_std", "must be finite and > 0");
  require(std::isfinite(huber_k) && huber_k >= 1, "huber_k", "must be finite and >= 1");
  require(std::isfinite(noise_memory) && noise_memory >= 1, "noise_memory", "must be finite and >= 1");
  require(std::isfinite(step_std) && step_std >= 0, "step_std", "must be finite and >= 0");
  require(std::isfinite(calibration_lag_hours) && calibration_lag_hours >= 0, "calibration_lag_hours",
          "must be finite and >= 0");
  require(std::isfinite(calibration_memory) && calibration_memory >= 1, "calibration_memory", "must be finite and >= 1");
}

Forecast forecast(const TrendState& st, const TrendParams& trend, double s) {
  const Eigen::Vector3d h(1.0, s, 0.5 * s * s);
  // Future acceleration: wear does not heal, so its random walk is folded to non-negative increments; the
  // level it adds by s hours, of variance d2 = q s^5 / 20 if unfolded, is approximated by the moments of the
  // half-normal: mean sqrt(2 / pi) d, variance (1 - 2 / pi) d^2.
  const double s5 = s * s * s * s * s;
  const double d2 = trend.forecast_diffusion * trend.acceleration_diffusion * st.inflation * s5 / 20.0;
  constexpr double kTwoOverPi = 0.6366197723675814;
  Forecast f;
  f.mean = h.dot(st.x) + std::sqrt(kTwoOverPi * d2);
  f.var = st.inflation * h.dot(st.p * h) + (1.0 - kTwoOverPi) * d2 + trend.forecast_diffusion * trend.level_diffusion * s;
  return f;
}

DegradationTrend::DegradationTrend(TrendParams params) : params_(params) { params_.validate(); }

void DegradationTrend::predict(double dt, bool discontinuity) {
  Eigen::Matrix3d f;
  f << 1.0, dt, 0.5 * dt * dt, 0.0, 1.0, dt, 0.0, 0.0, 1.0;
  // Adaptive process noise: when this channel's own forecasts missed by more than their variance, the
  // acceleration is allowed to change faster by the same factor (the filter lagged accelerating wear).
  const double q = params_.acceleration_diffusion * state_.inflation, d2 = dt * dt, d3 = d2 * dt;
  Eigen::Matrix3d qm;
  qm << d3 * d2 / 20.0, d2 * d2 / 8.0, d3 / 6.0,  //
      d2 * d2 / 8.0, d3 / 3.0, d2 / 2.0,            //
      d3 / 6.0, d2 / 2.0, dt;
  qm *= q;
  qm(0, 0) += params_.level_diffusion * dt;
  state_.x = f * state_.x;
  state_.p = f * state_.p * f.transpose() + qm;
  if (discontinuity) state_.p(0, 0) += params_.step_std * params_.step_std;
}

bool DegradationTrend::observe(std::int64_t time_ns, double y, double noise_std, bool discontinuity) {
  if (!std::isfinite(y) || !std::isfinite(noise_std) || noise_std < 0 || (started() && time_ns <= state_.time_ns)) {
    ++refused_;
    return false;
  }
  const double r_base = std::pow(std::max(noise_std, params_.min_noise_std), 2);
  if (!started()) {
    state_.x << y, 0.0, 0.0;
    state_.p.setZero();
    state_.p(0, 0) = r_base;
    state_.p(1, 1) = params_.initial_slope_std * params_.initial_slope_std;
    state_.p(2, 2) = params_.initial_acceleration_std * params_.initial_acceleration_std;
    state_.time_ns = time_ns;
    reference_ = state_;
    ++observations_;
    return true;
  }
  predict(static_cast<double>(time_ns - state_.time_ns) / kNsPerHour, discontinuity);
  state_.time_ns = time_ns;
  const double p00 = state_.p(0, 0);
  const double s = p00 + r_base * noise_scale_;
  const double v = y - state_.x[0];
  const double z = v / std::sqrt(s);
  // Huber: an innovation beyond k sigma moves the state as one of exactly k sigma would.
  double w = 1.0;
  if (std::abs(z) > params_.huber_k) {
    w = params_.huber_k / std::abs(z);
    ++downweighted_;
  }
  const Eigen::Vector3d ph = state_.p.col(0);
  state_.x += ph * (w * v / s);
  state_.p -= (w / s) * ph * ph.transpose();
  state_.p = 0.5 * (state_.p + state_.p.transpose());
  // Running scale of the measurement noise over its healthy value: E[v^2] = P00 + R. The excess is clipped at
  // k^2 times the current scale, so one spike cannot inflate it; never below the healthy value.
  const double excess = std::max(v * v - p00, 0.0) / r_base;
  const double alpha = 1.0 / params_.noise_memory;
  noise_scale_ = std::max(1.0, (1.0 - alpha) * noise_scale_ +
                                   alpha * std::min(excess, params_.huber_k * params_.huber_k * noise_scale_));
  calibrate(y, r_base * noise_scale_, discontinuity);
  ++observations_;
  return true;
}

void DegradationTrend::calibrate(double y, double r, bool discontinuity) {
  if (params_.calibration_lag_hours <= 0) return;
  if (discontinuity) {  // a level step is not a forecast error of the trend: restart the check from here
    reference_ = state_;
    return;
  }
  const double lag = static_cast<double>(state_.time_ns - reference_.time_ns) / kNsPerHour;
  if (lag < params_.calibration_lag_hours) return;
  TrendState ref = reference_;
  ref.inflation = 1.0;  // the model's own forecast: the inflation measures it, it does not correct itself
  const Forecast f = forecast(ref, params_, lag);
  const double e2 = (y - f.mean) * (y - f.mean) / std::max(f.var + r, 1e-300);
  const double alpha = 1.0 / params_.calibration_memory;
  error_ms_ = (1.0 - alpha) * error_ms_ + alpha * std::min(e2, params_.huber_k * params_.huber_k * std::max(error_ms_, 1.0));
  state_.inflation = std::max(1.0, error_ms_);
  ++checks_;
  reference_ = state_;
}

namespace {

// The parameters a trend was written with (restore compares them with its own).
template <class IO, class P>
void trend_param_fields(IO io, P& p) {
  io(p.acceleration_diffusion);
  io(p.forecast_diffusion);
  io(p.level_diffusion);
  io(p.initial_slope_std);
  io(p.initial_acceleration_std);
  io(p.min_noise_std);
  io(p.huber_k);
  io(p.noise_memory);
  io(p.step_std);
  io(p.calibration_lag_hours);
  io(p.calibration_memory);
}

}  // namespace

template <class IO, class Self>
void DegradationTrend::fields(IO io, Self& t) {
  io(t.state_.x);  // throws on another state size
  io(t.state_.p);
  io(t.state_.time_ns);
  io(t.noise_scale_);
  io(t.state_.inflation);
  io(t.reference_.x);
  io(t.reference_.p);
  io(t.reference_.time_ns);
  io(t.reference_.inflation);
  io(t.error_ms_);
  io(t.checks_);
  io(t.observations_);
  io(t.refused_);
  io(t.downweighted_);
}

void DegradationTrend::save(estimation::StateWriter& out) const {
  out.begin(kTag, kVersion);
  trend_param_fields(estimation::SaveFields{out}, params_);
  fields(estimation::SaveFields{out}, *this);
}

DegradationTrend DegradationTrend::restore(estimation::StateReader& in, const TrendParams& params) {
  in.expect(kTag, kVersion);
  TrendParams saved;
  trend_param_fields(estimation::RestoreFields{in}, saved);
  if (saved.acceleration_diffusion != params.acceleration_diffusion ||
      saved.forecast_diffusion != params.forecast_diffusion || saved.level_diffusion != params.level_diffusion ||
      saved.initial_slope_std != params.initial_slope_std ||
      saved.initial_acceleration_std != params.initial_acceleration_std || saved.min_noise_std != params.min_noise_std ||
      saved.huber_k != params.huber_k || saved.noise_memory != params.noise_memory || saved.step_std != params.step_std ||
      saved.calibration_lag_hours != params.calibration_lag_hours || saved.calibration_memory != params.calibration_memory) {
    throw estimation::StateError("the degradation trend was written with other prognosis trend parameters");
  }
  DegradationTrend t(params);
  fields(estimation::RestoreFields{in}, t);
  return t;
}

}  // namespace causal::prognosis
