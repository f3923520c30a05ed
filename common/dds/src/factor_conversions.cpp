#include "causal/dds/factor_conversions.hpp"

#include <algorithm>
#include <limits>
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

void to_outcome_factors(const FactorContext& context, const pipeline::FactorReport& report,
                        causal_twin::OutcomeFactors& out) {
  const estimation::SvarLayout& layout = *context.layout;
  const int k = report.outcome;
  out.outcome(static_cast<uint16_t>(k + 1));
  out.outcome_name(context.channel_names.at(static_cast<std::size_t>(k)));
  std::vector<std::string> names;
  names.reserve(static_cast<std::size_t>(layout.factor_count(k)));
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

std::vector<causal_twin::CausalFactorBatch> to_causal_factor_batches(const FactorContext& context,
                                                                     const std::vector<pipeline::FactorReport>& reports) {
  const estimation::SvarLayout& layout = *context.layout;
  std::vector<causal_twin::CausalFactorBatch> batches;
  std::vector<std::vector<const pipeline::FactorReport*>> members;
  for (const auto& r : reports) {
    const auto kind =
        r.kind == pipeline::EstimateKind::Filter ? causal_twin::FILTER : causal_twin::FIXED_LAG_SMOOTHER;
    std::size_t at = 0;
    while (at < batches.size() && !(batches[at].kind() == kind && batches[at].sample_index() == r.sample_index)) ++at;
    if (at == batches.size()) {  // a handful of batches per call: a linear search is cheapest
      causal_twin::CausalFactorBatch b;
      b.asset_group(context.asset_group);
      b.kind(kind);
      b.time_scale(context.time_scale);
      b.feature(context.feature);
      b.channel_count(static_cast<uint16_t>(layout.channels()));
      b.lag_order(static_cast<uint16_t>(layout.lag_order()));
      b.sample_index(r.sample_index);
      b.time_ns(r.time_ns);
      b.order_confidence(context.order_confidence);
      b.order_source(context.order_source);
      batches.push_back(std::move(b));
      members.emplace_back();
    }
    members[at].push_back(&r);
  }
  for (std::size_t i = 0; i < batches.size(); ++i) {
    auto& m = members[i];
    std::stable_sort(m.begin(), m.end(), [](const auto* a, const auto* b) { return a->outcome < b->outcome; });
    auto& blocks = batches[i].outcomes();
    blocks.resize(m.size());
    for (std::size_t j = 0; j < m.size(); ++j) to_outcome_factors(context, *m[j], blocks[j]);
  }
  return batches;
}

std::string validate_causal_factor_batch(const causal_twin::CausalFactorBatch& in) {
  if (in.channel_count() < 2) return "channel_count must be >= 2";
  if (in.outcomes().empty()) return "the batch has no outcome block";
  int previous = 0;
  for (const auto& o : in.outcomes()) {
    const std::string where = "outcome " + std::to_string(o.outcome());
    if (o.outcome() < 1 || o.outcome() > in.channel_count()) {
      return where + " is outside 1.." + std::to_string(in.channel_count());
    }
    if (o.outcome() <= previous) return where + " is not after outcome " + std::to_string(previous) + " (order, repeat)";
    previous = o.outcome();
    if (o.factors().size() != o.factor_names().size() || o.factor_std().size() != o.factors().size()) {
      return where + ": factor_names, factors and factor_std differ in length";
    }
    const std::size_t expected = triangle_size(o.factors().size());
    if (!o.factor_covariance().empty() && o.factor_covariance().size() != expected) {
      return where + ": factor_covariance has " + std::to_string(o.factor_covariance().size()) +
             " values, expected 0 or " + std::to_string(expected) + " (lower triangle of " +
             std::to_string(o.factors().size()) + " factors)";
    }
  }
  return {};
}

std::vector<FactorMessage> from_causal_factor_batch(const causal_twin::CausalFactorBatch& in) {
  std::vector<FactorMessage> out;
  out.reserve(in.outcomes().size());
  for (const auto& o : in.outcomes()) {
    FactorMessage m;
    m.asset_group = in.asset_group();
    m.outcome = o.outcome() - 1;
    m.kind = in.kind();
    m.time_scale = in.time_scale();
    m.feature = in.feature();
    m.outcome_name = o.outcome_name();
    m.channel_count = in.channel_count();
    m.lag_order = in.lag_order();
    m.sample_index = in.sample_index();
    m.time_ns = in.time_ns();
    m.factor_names.assign(o.factor_names().begin(), o.factor_names().end());
    m.factors = Eigen::Map<const Eigen::VectorXd>(o.factors().data(), static_cast<Eigen::Index>(o.factors().size()));
    m.factor_std =
        Eigen::Map<const Eigen::VectorXd>(o.factor_std().data(), static_cast<Eigen::Index>(o.factor_std().size()));
    if (!o.factor_covariance().empty()) {
      m.covariance = unpack_lower_triangle(o.factor_covariance(), static_cast<int>(o.factors().size()));
    }
    m.innovation_count = o.innovation_count();
    m.innovation_mean = o.innovation_mean();
    m.nis_mean = o.nis_mean();
    m.last_innovation = o.last_innovation();
    m.last_innovation_variance = o.last_innovation_variance();
    m.rejected_samples = o.rejected_samples();
    out.push_back(std::move(m));
  }
  return out;
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
