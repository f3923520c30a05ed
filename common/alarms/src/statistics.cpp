#include "causal/alarms/statistics.hpp"

#include "causal/estimation/normal_quantile.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace causal::alarms {

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  const double upper = v[mid];
  if (v.size() % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
  return 0.5 * (lower + upper);
}

RobustStats robust_stats(const std::vector<double>& v, double relative_floor, double absolute_floor) {
  RobustStats s;
  std::vector<double> finite;
  finite.reserve(v.size());
  for (double x : v)
    if (std::isfinite(x)) finite.push_back(x);
  s.count = finite.size();
  if (finite.size() < 2) return s;
  s.location = median(finite);
  std::vector<double> dev(finite.size());
  for (std::size_t i = 0; i < finite.size(); ++i) dev[i] = std::abs(finite[i] - s.location);
  // 1.4826 = 1 / Phi^-1(3/4): makes MAD a consistent estimator of sigma for Gaussian data.
  double scale = 1.4826 * median(dev);
  double mean = 0.0;
  for (double x : finite) mean += x;
  mean /= static_cast<double>(finite.size());
  double c0 = 0.0, c1 = 0.0;
  for (std::size_t i = 0; i < finite.size(); ++i) {
    c0 += (finite[i] - mean) * (finite[i] - mean);
    if (i > 0) c1 += (finite[i] - mean) * (finite[i - 1] - mean);
  }
  s.lag1_autocorr = c0 > 0.0 ? c1 / c0 : 0.0;
  if (!(scale > 0.0)) scale = std::sqrt(c0 / static_cast<double>(finite.size() - 1));
  if (!(scale > 0.0)) scale = relative_floor * std::abs(s.location);
  if (!(scale > 0.0)) scale = absolute_floor;
  s.scale = scale;
  s.valid = true;
  return s;
}

// One field list for save and restore (state_fields.hpp): S is const when saving.
template <class IO, class S>
void robust_stats_fields(IO io, S& s) {
  io.tag("robust_stats", 1);
  io(s.location, s.scale, s.lag1_autocorr);
  io.template as<std::uint64_t>(s.count);
  io(s.valid);
}

void save(estimation::StateWriter& out, const RobustStats& stats) { robust_stats_fields(estimation::SaveFields{out}, stats); }

void restore(estimation::StateReader& in, RobustStats& stats) {
  RobustStats s;
  robust_stats_fields(estimation::RestoreFields{in}, s);
  // robust_stats() promises a positive, finite scale (its fallbacks): every z divides by it.
  if (!(std::isfinite(s.scale) && s.scale > 0.0) || (s.valid && !std::isfinite(s.location))) {
    throw estimation::StateError("checkpoint: robust_stats section holds an invalid location or scale");
  }
  stats = s;
}

double normal_upper_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("normal_upper_quantile: p must be in (0, 1)");
  return -estimation::normal_quantile(p);  // upper tail p = lower tail p, mirrored
}

double chi_square_upper_quantile(int dof, double p) {
  if (dof < 1) throw std::invalid_argument("chi_square_upper_quantile: dof must be >= 1");
  // Wilson-Hilferty: (X/nu)^(1/3) ~ N(1 - 2/(9 nu), 2/(9 nu)).
  const double nu = static_cast<double>(dof);
  const double z = normal_upper_quantile(p);
  const double v = 2.0 / (9.0 * nu);
  const double c = 1.0 - v + z * std::sqrt(v);
  return nu * c * c * c;
}

double cusum_arl0(double k, double h) {
  if (!(k > 0.0)) throw std::invalid_argument("cusum_arl0: k must be > 0");
  const double b = h + 1.166;
  const double x = 2.0 * k * b;
  return (std::exp(x) - x - 1.0) / (2.0 * k * k);
}

double cusum_threshold_for_arl0(double k, double target_arl0) {
  if (!(k > 0.0)) throw std::invalid_argument("cusum_threshold_for_arl0: k must be > 0");
  if (!(target_arl0 > 1.0)) throw std::invalid_argument("cusum_threshold_for_arl0: target ARL0 must be > 1");
  double lo = 0.0, hi = 1.0;
  while (cusum_arl0(k, hi) < target_arl0) hi *= 2.0;
  for (int it = 0; it < 200 && hi - lo > 1e-10; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (cusum_arl0(k, mid) < target_arl0)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace causal::alarms
