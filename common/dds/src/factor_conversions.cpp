#include "causal/dds/factor_conversions.hpp"

#include <stdexcept>

namespace causal::dds {

namespace {
// Number of values in the packed lower triangle of a d x d matrix.
std::size_t triangle_size(std::size_t d) { return d * (d + 1) / 2; }
}  // namespace

std::vector<double> pack_lower_triangle(const Eigen::MatrixXd& p) {
  if (p.rows() != p.cols()) {
    throw std::invalid_argument("pack_lower_triangle: matrix is " + std::to_string(p.rows()) + " x " +
                                std::to_string(p.cols()) + ", not square");
  }
  std::vector<double> out;
  out.reserve(triangle_size(static_cast<std::size_t>(p.rows())));
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    for (Eigen::Index j = 0; j <= i; ++j) out.push_back(p(i, j));
  }
  return out;
}

Eigen::MatrixXd unpack_lower_triangle(const std::vector<double>& packed, int d) {
  if (d < 0 || packed.size() != triangle_size(static_cast<std::size_t>(d))) return {};
  Eigen::MatrixXd p(d, d);
  std::size_t at = 0;
  for (int i = 0; i < d; ++i) {
    for (int j = 0; j <= i; ++j) {
      p(i, j) = packed[at];
      p(j, i) = packed[at];  // mirrored: exactly symmetric by construction
      ++at;
    }
  }
  return p;
}

void to_causal_factors(const FactorContext& context, const pipeline::FactorReport& report,
                       causal_twin::CausalFactors& out) {
  const SvarLayout& layout = *context.layout;
  const int k = report.outcome;
  out.asset_group(context.asset_group);
  out.outcome(static_cast<uint16_t>(k + 1));
  out.kind(report.kind == pipeline::EstimateKind::Filter ? causal_twin::FILTER : causal_twin::FIXED_LAG_SMOOTHER);
  out.time_scale(context.time_scale);
  out.feature(context.feature);
  out.outcome_name(context.channel_names.at(static_cast<std::size_t>(k)));
  out.channel_count(static_cast<uint16_t>(layout.channels()));
  out.lag_order(static_cast<uint16_t>(layout.lag_order()));
  out.sample_index(report.sample_index);
  out.time_ns(report.time_ns);
  std::vector<std::string> names;
  for (int i = 0; i < layout.factor_count(k); ++i) names.push_back(layout.factor_name(k, i));
  out.factor_names(std::move(names));
  out.factors(std::vector<double>(report.factors.data(), report.factors.data() + report.factors.size()));
  out.factor_std(std::vector<double>(report.std_devs.data(), report.std_devs.data() + report.std_devs.size()));
  const Eigen::MatrixXd& p = report.covariance;
  const bool has_covariance = p.size() > 0 && p.rows() == p.cols() && p.rows() == report.factors.size();
  out.factor_covariance(has_covariance ? pack_lower_triangle(p) : std::vector<double>{});
  out.innovation_count(static_cast<uint32_t>(report.innovation_count));
  out.innovation_mean(report.innovation_mean);
  out.nis_mean(report.nis_mean);
  out.last_innovation(report.last_innovation);
  out.last_innovation_variance(report.last_innovation_variance);
  out.rejected_samples(static_cast<uint32_t>(report.rejected));
  out.process_noise_q(report.q);
  out.measurement_noise_r(report.r);
}

std::string validate_causal_factors(const causal_twin::CausalFactors& in) {
  if (in.channel_count() < 2) return "channel_count must be >= 2";
  if (in.outcome() < 1 || in.outcome() > in.channel_count()) {
    return "outcome " + std::to_string(in.outcome()) + " is outside 1.." + std::to_string(in.channel_count());
  }
  if (in.factors().size() != in.factor_names().size() || in.factor_std().size() != in.factors().size()) {
    return "factor_names, factors and factor_std differ in length";
  }
  const std::size_t expected = triangle_size(in.factors().size());
  if (!in.factor_covariance().empty() && in.factor_covariance().size() != expected) {
    return "factor_covariance has " + std::to_string(in.factor_covariance().size()) + " values, expected 0 or " +
           std::to_string(expected) + " (lower triangle of " + std::to_string(in.factors().size()) + " factors)";
  }
  return {};
}

FactorMessage from_causal_factors(const causal_twin::CausalFactors& in) {
  FactorMessage m;
  m.asset_group = in.asset_group();
  m.outcome = in.outcome() - 1;
  m.kind = in.kind();
  m.time_scale = in.time_scale();
  m.feature = in.feature();
  m.outcome_name = in.outcome_name();
  m.channel_count = in.channel_count();
  m.lag_order = in.lag_order();
  m.sample_index = in.sample_index();
  m.time_ns = in.time_ns();
  m.factor_names.assign(in.factor_names().begin(), in.factor_names().end());
  m.factors = Eigen::Map<const Eigen::VectorXd>(in.factors().data(), static_cast<Eigen::Index>(in.factors().size()));
  m.factor_std =
      Eigen::Map<const Eigen::VectorXd>(in.factor_std().data(), static_cast<Eigen::Index>(in.factor_std().size()));
  if (!in.factor_covariance().empty()) {
    m.covariance = unpack_lower_triangle(in.factor_covariance(), static_cast<int>(in.factors().size()));
  }
  m.innovation_count = in.innovation_count();
  m.innovation_mean = in.innovation_mean();
  m.nis_mean = in.nis_mean();
  m.last_innovation = in.last_innovation();
  m.last_innovation_variance = in.last_innovation_variance();
  m.rejected_samples = in.rejected_samples();
  return m;
}

const char* to_string(causal_twin::EstimateKind kind) {
  switch (kind) {
    case causal_twin::FILTER: return "filter";
    case causal_twin::FIXED_LAG_SMOOTHER: return "fixed-lag";
    case causal_twin::RTS_SMOOTHER: return "rts";
  }
  return "?";
}

const char* to_string(causal_twin::TimeScale scale) {
  return scale == causal_twin::SAMPLE_LEVEL ? "sample" : "condition";
}

}  // namespace causal::dds
