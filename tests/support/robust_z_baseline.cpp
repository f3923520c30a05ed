// Plain robust-z reference detector: see robust_z_baseline.hpp.
#include "robust_z_baseline.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace causal::testing {
namespace {

double median_of(std::vector<double> v) {
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  if (v.size() % 2 == 1) return v[m];
  const double upper = v[m];
  return 0.5 * (*std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m)) + upper);
}

}  // namespace

std::vector<RobustZChannel> robust_z_first_alarms(const Eigen::MatrixXd& values, const RobustZParams& p) {
  const auto n = static_cast<std::size_t>(values.rows());
  if (p.baseline_begin >= p.baseline_end || p.baseline_end > n) {
    throw std::invalid_argument("robust z: baseline rows [" + std::to_string(p.baseline_begin) + ", " +
                                std::to_string(p.baseline_end) + ") do not fit " + std::to_string(n) + " rows");
  }
  if (p.persistence < 1 || !(p.threshold > 0.0)) throw std::invalid_argument("robust z: bad threshold or persistence");
  std::vector<RobustZChannel> out(static_cast<std::size_t>(values.cols()));
  for (Eigen::Index c = 0; c < values.cols(); ++c) {
    RobustZChannel& ch = out[static_cast<std::size_t>(c)];
    std::vector<double> window;
    for (std::size_t i = p.baseline_begin; i < p.baseline_end; ++i) {
      const double x = values(static_cast<Eigen::Index>(i), c);
      if (std::isfinite(x)) window.push_back(x);
    }
    if (window.empty()) throw std::invalid_argument("robust z: channel " + std::to_string(c + 1) + " has no baseline value");
    ch.median = median_of(window);
    for (double& x : window) x = std::abs(x - ch.median);
    ch.scale = 1.4826 * median_of(window);
    if (!(ch.scale > 0.0)) throw std::invalid_argument("robust z: channel " + std::to_string(c + 1) + " has MAD 0");
    int run = 0;
    for (std::size_t i = p.baseline_end; i < n; ++i) {
      const double x = values(static_cast<Eigen::Index>(i), c);
      const bool exceeds = std::isfinite(x) && std::abs(x - ch.median) / ch.scale > p.threshold;
      run = exceeds ? run + 1 : 0;
      if (run >= p.persistence) {
        ch.first_alarm = i;
        break;
      }
    }
  }
  return out;
}

}  // namespace causal::testing
