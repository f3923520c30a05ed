#include "causal/analysis/uncertainty.hpp"

#include "posterior_draws.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace causal::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

EffectInterval nan_interval(Eigen::Index size) {
  return {Eigen::VectorXd::Constant(size, kNaN), Eigen::VectorXd::Constant(size, kNaN),
          Eigen::VectorXd::Constant(size, kNaN)};
}

// Effect quantities stacked into one vector: [immediate; steady_state; cumulative (impulse only)].
Eigen::VectorXd stack(const InterventionEffect& e) {
  Eigen::VectorXd v(e.immediate.size() + e.steady_state.size() + e.cumulative.size());
  v << e.immediate, e.steady_state, e.cumulative;
  return v;
}

void unstack(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, const Eigen::VectorXd& sd, Eigen::Index g,
             UncertainEffect& out) {
  out.immediate = {lo.segment(0, g), hi.segment(0, g), sd.segment(0, g)};
  out.steady_state = {lo.segment(g, g), hi.segment(g, g), sd.segment(g, g)};
  if (lo.size() > 2 * g) out.cumulative = {lo.segment(2 * g, g), hi.segment(2 * g, g), sd.segment(2 * g, g)};
}

void monte_carlo(const estimation::SvarLayout& layout, const FactorPosterior& posterior, const InterventionQuery& query,
                 const UncertaintyOptions& options, UncertainEffect& out) {
  const Eigen::Index g = layout.channels();
  detail::PosteriorSampler sampler(layout, posterior, options.seed);
  const Eigen::Index width = stack(out.point).size();
  std::vector<std::vector<double>> samples(static_cast<std::size_t>(width));
  for (int d = 0; d < options.draws; ++d) {
    const Eigen::VectorXd& x = sampler.next();
    const InterventionEffect e = predict_intervention(assemble_structural_model(layout, x), query);
    const Eigen::VectorXd v = stack(e);
    if (e.status != AnalysisStatus::ok || !v.allFinite()) {
      ++out.draws_rejected;
      continue;
    }
    ++out.draws_used;
    for (Eigen::Index i = 0; i < width; ++i) samples[static_cast<std::size_t>(i)].push_back(v(i));
  }
  if (out.draws_used < 2) return;
  Eigen::VectorXd lo(width), hi(width), sd(width);
  const double tail = 0.5 * (1.0 - options.coverage);
  for (Eigen::Index i = 0; i < width; ++i) {
    auto& s = samples[static_cast<std::size_t>(i)];
    const Eigen::Map<const Eigen::VectorXd> m(s.data(), static_cast<Eigen::Index>(s.size()));
    const double mean = m.mean();
    sd(i) = std::sqrt((m.array() - mean).square().sum() / static_cast<double>(s.size() - 1));
    std::sort(s.begin(), s.end());
    lo(i) = detail::percentile(s, tail);
    hi(i) = detail::percentile(s, 1.0 - tail);
  }
  unstack(lo, hi, sd, g, out);
  out.interval_valid = true;
}

void delta_method(const estimation::SvarLayout& layout, const FactorPosterior& posterior, const InterventionQuery& query,
                  const UncertaintyOptions& options, UncertainEffect& out) {
  const Eigen::Index g = layout.channels();
  const Eigen::VectorXd f0 = stack(out.point);
  Eigen::VectorXd variance = Eigen::VectorXd::Zero(f0.size());
  for (int k = 0; k < layout.channels(); ++k) {
    const int fk = layout.factor_count(k);
    Eigen::MatrixXd jac(f0.size(), fk);  // J_k, central differences (second-order accurate)
    for (int i = 0; i < fk; ++i) {
      const int idx = layout.offset(k) + i;
      const double h = options.relative_step * std::max(1.0, std::abs(posterior.mean(idx)));
      Eigen::VectorXd xp = posterior.mean;
      Eigen::VectorXd xm = posterior.mean;
      xp(idx) += h;
      xm(idx) -= h;
      const InterventionEffect ep = predict_intervention(assemble_structural_model(layout, xp), query);
      const InterventionEffect em = predict_intervention(assemble_structural_model(layout, xm), query);
      if (ep.status != AnalysisStatus::ok || em.status != AnalysisStatus::ok) return;  // at the edge: no interval
      jac.col(i) = (stack(ep) - stack(em)) / (2.0 * h);
    }
    const Eigen::MatrixXd& p = posterior.blocks[static_cast<std::size_t>(k)];
    variance += (jac * p * jac.transpose()).diagonal().cwiseMax(0.0);
  }
  const Eigen::VectorXd sd = variance.cwiseSqrt();
  const double z = estimation::normal_quantile(0.5 * (1.0 + options.coverage));
  unstack(f0 - z * sd, f0 + z * sd, sd, g, out);
  out.interval_valid = sd.allFinite();
}

}  // namespace

const char* to_string(IntervalMethod method) {
  return method == IntervalMethod::monte_carlo ? "monte_carlo" : "delta_method";
}


UncertainEffect predict_intervention_with_uncertainty(const estimation::SvarLayout& layout, const FactorPosterior& posterior,
                                                      const InterventionQuery& query,
                                                      const UncertaintyOptions& options) {
  if (!(options.coverage > 0.0 && options.coverage < 1.0)) {
    throw std::invalid_argument("uncertainty: coverage must be in (0, 1)");
  }
  if (options.method == IntervalMethod::monte_carlo && options.draws < 2) {
    throw std::invalid_argument("uncertainty: need at least 2 Monte Carlo draws");
  }
  if (!(options.relative_step > 0.0)) throw std::invalid_argument("uncertainty: relative_step must be > 0");
  validate_posterior(layout, posterior);

  UncertainEffect out;
  out.coverage = options.coverage;
  out.method = options.method;
  out.point = predict_intervention(assemble_structural_model(layout, posterior.mean), query);
  const Eigen::Index g = layout.channels();
  out.immediate = nan_interval(g);
  out.steady_state = nan_interval(g);
  out.cumulative = query.kind == InterventionKind::impulse ? nan_interval(g) : EffectInterval{};
  if (out.point.status != AnalysisStatus::ok) return out;
  InterventionQuery no_path = query;  // draws need only the summary quantities
  no_path.horizon = 0;
  if (options.method == IntervalMethod::monte_carlo) {
    monte_carlo(layout, posterior, no_path, options, out);
  } else {
    delta_method(layout, posterior, no_path, options, out);
  }
  return out;
}

}  // namespace causal::analysis
