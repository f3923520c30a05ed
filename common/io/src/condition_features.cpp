// Batch condition features (two-pass central moments) and feature-name parsing.
#include "causal/io/condition_features.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "moments.hpp"
#include "text_scan.hpp"

namespace causal::io {

std::optional<ConditionFeature> parse_condition_feature(std::string_view name) {
  const std::string n = detail::to_lower(detail::trim(name));
  if (n == "rms") return ConditionFeature::Rms;
  if (n == "meanabs" || n == "mean_abs") return ConditionFeature::MeanAbs;
  if (n == "kurtosis") return ConditionFeature::Kurtosis;
  if (n == "peak" || n == "peakabs" || n == "peak_abs") return ConditionFeature::Peak;
  return std::nullopt;
}

std::string to_string(ConditionFeature feature) {
  switch (feature) {
    case ConditionFeature::Rms: return "rms";
    case ConditionFeature::MeanAbs: return "meanabs";
    case ConditionFeature::Kurtosis: return "kurtosis";
    case ConditionFeature::Peak: return "peak";
  }
  return "unknown";
}

std::string derived_column_suffix(ConditionFeature feature) {
  return feature == ConditionFeature::Peak ? std::string("_peakabs") : "_" + to_string(feature);
}

namespace detail {

// "Zero to rounding": the sample spread is below ~64 ulps
// of the signal's magnitude, where rounding in the mean alone can create a spurious m2.
double kurtosis_from_sums(double n, double m2, double m4, double peak) {
  const double eps = std::numeric_limits<double>::epsilon();
  const double var = m2 / n;
  const double floor_var = (64.0 * eps * peak) * (64.0 * eps * peak);
  if (!(var > floor_var) || var <= 0.0) return std::numeric_limits<double>::quiet_NaN();
  return n * m4 / (m2 * m2);
}

}  // namespace detail

Eigen::VectorXd compute_condition_feature(const Eigen::Ref<const Eigen::MatrixXd>& samples,
                                          ConditionFeature feature) {
  const Eigen::Index n_rows = samples.rows();
  const Eigen::Index g = samples.cols();
  // Rows with any non-finite value are excluded, as in ConditionAccumulator::add.
  std::vector<Eigen::Index> ok;
  ok.reserve(static_cast<std::size_t>(n_rows));
  for (Eigen::Index r = 0; r < n_rows; ++r) {
    if (samples.row(r).allFinite()) ok.push_back(r);
  }
  Eigen::VectorXd out = Eigen::VectorXd::Constant(g, std::numeric_limits<double>::quiet_NaN());
  if (ok.empty()) return out;
  const auto n = static_cast<double>(ok.size());
  for (Eigen::Index c = 0; c < g; ++c) {
    const auto col = samples.col(c);
    switch (feature) {
      case ConditionFeature::Rms: {
        double ss = 0.0;
        for (Eigen::Index r : ok) ss += col(r) * col(r);
        out(c) = std::sqrt(ss / n);
        break;
      }
      case ConditionFeature::MeanAbs: {
        double sa = 0.0;
        for (Eigen::Index r : ok) sa += std::abs(col(r));
        out(c) = sa / n;
        break;
      }
      case ConditionFeature::Peak: {
        double p = 0.0;
        for (Eigen::Index r : ok) p = std::max(p, std::abs(col(r)));
        out(c) = p;
        break;
      }
      case ConditionFeature::Kurtosis: {
        // Two passes: mean first, then central sums, so no cancellation of large raw moments.
        double s = 0.0, p = 0.0;
        for (Eigen::Index r : ok) {
          s += col(r);
          p = std::max(p, std::abs(col(r)));
        }
        const double mean = s / n;
        double m2 = 0.0, m4 = 0.0;
        for (Eigen::Index r : ok) {
          const double d = col(r) - mean;
          const double d2 = d * d;
          m2 += d2;
          m4 += d2 * d2;
        }
        out(c) = detail::kurtosis_from_sums(n, m2, m4, p);
        break;
      }
    }
  }
  return out;
}

}  // namespace causal::io
