#include "causal/innovation_stats.hpp"

#include <cmath>
#include <limits>

#include "causal/svar_kalman_filter.hpp"

namespace causal {

void InnovationAccumulator::add(double e, double s) {
  if (!std::isfinite(e) || !std::isfinite(s) || !(s > 0.0)) return;
  ++count_;
  sum_e_ += e;
  sum_e2_ += e * e;
  sum_nis_ += e * e / s;
}

double InnovationAccumulator::mean() const {
  return count_ ? sum_e_ / static_cast<double>(count_) : std::numeric_limits<double>::quiet_NaN();
}

double InnovationAccumulator::mean_square() const {
  return count_ ? sum_e2_ / static_cast<double>(count_) : std::numeric_limits<double>::quiet_NaN();
}

double InnovationAccumulator::mean_nis() const {
  return count_ ? sum_nis_ / static_cast<double>(count_) : std::numeric_limits<double>::quiet_NaN();
}

void InnovationStats::add(const SvarKalmanFilter& filter) {
  for (int k = 0; k < channels(); ++k) {
    acc_[k].add(filter.last_innovation(k), filter.last_innovation_variance(k));
  }
}

void InnovationStats::reset() {
  for (auto& a : acc_) a.reset();
}

}  // namespace causal
