#include "causal/analysis/bounded_answer.hpp"

#include "intervention_draw.hpp"
#include "posterior_draws.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

namespace causal::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

EffectSummary nan_summary(Eigen::Index g) {
  return {Eigen::VectorXd::Constant(g, kNaN), Eigen::VectorXd::Constant(g, kNaN), Eigen::VectorXd::Constant(g, kNaN)};
}

// Per channel: median and the central `coverage` interval of the draws (columns = channels).
EffectSummary summarise(const std::vector<Eigen::VectorXd>& draws, Eigen::Index g, double coverage) {
  EffectSummary s = nan_summary(g);
  if (draws.empty()) return s;
  const double tail = 0.5 * (1.0 - coverage);
  std::vector<double> column(draws.size());
  for (Eigen::Index k = 0; k < g; ++k) {
    for (std::size_t d = 0; d < draws.size(); ++d) column[d] = draws[d](k);
    std::sort(column.begin(), column.end());
    s.median(k) = detail::percentile(column, 0.5);
    s.lower(k) = detail::percentile(column, tail);
    s.upper(k) = detail::percentile(column, 1.0 - tail);
  }
  return s;
}

std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

// One draw (or the posterior mean) reduced to what the rule needs.
struct DrawEffect {
  AnalysisStatus status = AnalysisStatus::ok;
  Eigen::VectorXd immediate, at_horizon, long_run;  // long_run only when status == ok
};

// Spectral radius of the model as estimated; NaN when (I - A0) is singular or the model non-finite.
double own_radius(const StructuralModel& model) { return check_dynamics(model).spectral_radius; }

DrawEffect evaluate(const StructuralModel& model, const InterventionQuery& query, int horizon) {
  InterventionQuery q = query;
  q.horizon = horizon + 1;  // path rows 0..H
  const InterventionEffect e = detail::predict_intervention_draw(model, q);
  DrawEffect out;
  out.status = e.status;
  // A model that does not settle on its own describes trending data: a steady state of its intervened
  // system extrapolates to a regime the data never showed (and on simulated explosive systems it was
  // confidently wrong-signed), so the draw counts as unstable.
  if (out.status == AnalysisStatus::ok && !detail::settles(model)) out.status = AnalysisStatus::unstable;
  out.immediate = e.immediate;
  if (query.kind == InterventionKind::sustained) {
    out.at_horizon = e.path.row(horizon).transpose();
    out.long_run = e.steady_state;
  } else {
    out.at_horizon = e.path.colwise().sum().transpose();  // cumulative change over n0 .. n0 + H
    out.long_run = e.cumulative;
  }
  // A draw whose path cannot be formed (singular instantaneous part, overflow) has no effect at all.
  if (out.status == AnalysisStatus::ok && !(out.long_run.allFinite() && out.at_horizon.allFinite())) {
    out.status = AnalysisStatus::non_finite_input;
  }
  if (out.status == AnalysisStatus::unstable && !out.at_horizon.allFinite()) out.status = AnalysisStatus::non_finite_input;
  return out;
}

}  // namespace

const char* to_string(AnswerKind kind) {
  switch (kind) {
    case AnswerKind::steady_state: return "steady_state";
    case AnswerKind::horizon: return "horizon";
    case AnswerKind::refused: return "refused";
  }
  return "unknown";
}

void validate_rule(const AnswerRule& rule) {
  if (!(rule.max_stable_radius > 0.0 && rule.max_stable_radius < 1.0)) {
    throw std::invalid_argument("answer rule: max_stable_radius must be in (0, 1)");
  }
  if (!(rule.max_unstable_share >= 0.0 && rule.max_unstable_share <= 1.0)) {
    throw std::invalid_argument("answer rule: max_unstable_share must be in [0, 1]");
  }
  if (!(rule.refuse_unstable_share >= 0.0 && rule.refuse_unstable_share <= 1.0)) {
    throw std::invalid_argument("answer rule: refuse_unstable_share must be in [0, 1]");
  }
  if (rule.horizon_snapshots < 1) throw std::invalid_argument("answer rule: horizon_snapshots must be >= 1");
}

BoundedAnswer answer_intervention(const estimation::SvarLayout& layout, const FactorPosterior& posterior,
                                  const InterventionQuery& query, const AnswerRule& rule,
                                  const UncertaintyOptions& options) {
  validate_rule(rule);
  if (!(options.coverage > 0.0 && options.coverage < 1.0)) throw std::invalid_argument("answer: coverage must be in (0, 1)");
  if (options.draws < 2) throw std::invalid_argument("answer: need at least 2 Monte Carlo draws");
  validate_posterior(layout, posterior);
  const Eigen::Index g = layout.channels();
  const int h = rule.horizon_snapshots;

  BoundedAnswer out;
  out.coverage = options.coverage;
  out.immediate = nan_summary(g);
  out.effect = nan_summary(g);

  // The point model decides stability; its effect is NOT the answer (the median of the draws is).
  InterventionQuery point_query = query;
  point_query.horizon = 0;
  const StructuralModel point_model = assemble_structural_model(layout, posterior.mean);
  const InterventionEffect point = predict_intervention(point_model, point_query);
  out.status = point.status;
  // The larger of the model and the intervened system (NaN stays NaN: std::max keeps its first argument).
  out.spectral_radius = std::max(point.spectral_radius, own_radius(point_model));
  if (point.status == AnalysisStatus::not_identifiable || point.status == AnalysisStatus::non_finite_input) {
    out.reason = std::string("no effect can be predicted: ") + point.message;
    return out;
  }

  detail::PosteriorSampler sampler(layout, posterior, options.seed);
  std::vector<Eigen::VectorXd> now_all, horizon_all, now_stable, long_run_stable;
  for (int d = 0; d < options.draws; ++d) {
    const DrawEffect e = evaluate(assemble_structural_model(layout, sampler.next()), query, h);
    ++out.draws;
    if (e.status == AnalysisStatus::not_identifiable || e.status == AnalysisStatus::non_finite_input) {
      ++out.singular_draws;
      continue;
    }
    now_all.push_back(e.immediate);
    horizon_all.push_back(e.at_horizon);
    if (e.status == AnalysisStatus::unstable) {
      ++out.unstable_draws;
      continue;
    }
    now_stable.push_back(e.immediate);
    long_run_stable.push_back(e.long_run);
  }

  const double rho = out.spectral_radius;
  const double unstable = out.unstable_share();
  const double singular = static_cast<double>(out.singular_draws) / out.draws;
  const std::string counts = std::to_string(out.unstable_draws) + "/" + std::to_string(out.draws) + " draws unstable";
  if (singular > rule.refuse_unstable_share || horizon_all.size() < 2) {
    out.reason = "the instantaneous equations are singular in " + std::to_string(out.singular_draws) + "/" +
                 std::to_string(out.draws) + " posterior draws: the effect is not identifiable";
    return out;
  }
  if (rho <= rule.max_stable_radius && unstable <= rule.max_unstable_share && long_run_stable.size() >= 2) {
    out.kind = AnswerKind::steady_state;
    out.draws_summarised = static_cast<int>(long_run_stable.size());
    out.immediate = summarise(now_stable, g, options.coverage);
    out.effect = summarise(long_run_stable, g, options.coverage);
    out.reason = fmt("the model settles: spectral radius %.3f <= %.3f", rho, rule.max_stable_radius) + " and " + counts +
                 fmt(" (<= %.0f %%)", 100.0 * rule.max_unstable_share);
    return out;
  }
  if (!(rho < 1.0 - 1e-9) && unstable > rule.refuse_unstable_share) {
    out.reason = fmt("the model is past a unit root (spectral radius %.3f >= 1) and ", rho) + counts +
                 fmt(" (> %.0f %%): the levels trend, no effect of an intervention can be predicted",
                     100.0 * rule.refuse_unstable_share);
    return out;
  }
  out.kind = AnswerKind::horizon;
  out.horizon_snapshots = h;
  out.draws_summarised = static_cast<int>(horizon_all.size());
  out.immediate = summarise(now_all, g, options.coverage);
  out.effect = summarise(horizon_all, g, options.coverage);
  out.reason = fmt("no reliable steady state (spectral radius %.3f, ", rho) + counts + "): effect after " +
               std::to_string(h) + " snapshots";
  return out;
}

}  // namespace causal::analysis
