#include "causal/analysis/bounded_answer.hpp"

#include "intervention_draw.hpp"
#include "posterior_draws.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include "causal/io/enum_names.hpp"

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

// model_settles: settles(model) when the caller computed it once for every query of this draw (then a
// sustained query skips its intervened dynamics where the model does not settle); nullopt computes it here,
// only where the intervened system is fine (the per-query way).
DrawEffect evaluate(const StructuralModel& model, const InterventionQuery& query, int horizon,
                    std::optional<bool> model_settles) {
  InterventionQuery q = query;
  q.horizon = horizon + 1;  // path rows 0..H
  // The per-query way (model_settles unknown) is also the way before the instability proof: the reference.
  const bool prove_unstable = model_settles.has_value();
  const InterventionEffect e = detail::predict_intervention_draw(model, q, model_settles.value_or(true), prove_unstable);
  DrawEffect out;
  out.status = e.status;
  // A model that does not settle on its own describes trending data: a steady state of its intervened
  // system extrapolates to a regime the data never showed (and on simulated explosive systems it was
  // confidently wrong-signed), so the draw counts as unstable.
  if (out.status == AnalysisStatus::ok && !(model_settles ? *model_settles : detail::settles(model, false))) {
    out.status = AnalysisStatus::unstable;
  }
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

// The draws of one query, kept until the rule decides which of them it summarises.
struct QueryDraws {
  std::vector<Eigen::VectorXd> now_all, horizon_all, now_stable, long_run_stable;
  bool open = false;  // the point model did not already decide a refusal
};

void add_draw(const DrawEffect& e, BoundedAnswer& out, QueryDraws& d) {
  ++out.draws;
  if (e.status == AnalysisStatus::not_identifiable || e.status == AnalysisStatus::non_finite_input) {
    ++out.singular_draws;
    return;
  }
  d.now_all.push_back(e.immediate);
  d.horizon_all.push_back(e.at_horizon);
  if (e.status == AnalysisStatus::unstable) {
    ++out.unstable_draws;
    return;
  }
  d.now_stable.push_back(e.immediate);
  d.long_run_stable.push_back(e.long_run);
}

// The point model decides stability; its effect is NOT the answer (the median of the draws is). False when it
// already refuses (not identifiable, non-finite): no draws are needed then.
bool start_answer(const StructuralModel& point_model, double own, const InterventionQuery& query, Eigen::Index g,
                  double coverage, BoundedAnswer& out) {
  out.coverage = coverage;
  out.immediate = nan_summary(g);
  out.effect = nan_summary(g);
  InterventionQuery point_query = query;
  point_query.horizon = 0;
  const InterventionEffect point = predict_intervention(point_model, point_query);
  out.status = point.status;
  // The larger of the model and the intervened system (NaN stays NaN: std::max keeps its first argument).
  out.spectral_radius = std::max(point.spectral_radius, own);
  if (point.status == AnalysisStatus::not_identifiable || point.status == AnalysisStatus::non_finite_input) {
    out.reason = std::string("no effect can be predicted: ") + point.message;
    return false;
  }
  return true;
}

// The rule of bounded_answer.hpp on the draws of one query.
void finish_answer(const QueryDraws& d, const AnswerRule& rule, Eigen::Index g, double coverage, BoundedAnswer& out) {
  const int h = rule.horizon_snapshots;
  const double rho = out.spectral_radius;
  const double unstable = out.unstable_share();
  const double singular = static_cast<double>(out.singular_draws) / out.draws;
  const std::string counts = std::to_string(out.unstable_draws) + "/" + std::to_string(out.draws) + " draws unstable";
  if (singular > rule.refuse_unstable_share || d.horizon_all.size() < 2) {
    out.reason = "the instantaneous equations are singular in " + std::to_string(out.singular_draws) + "/" +
                 std::to_string(out.draws) + " posterior draws: the effect is not identifiable";
    return;
  }
  if (rho <= rule.max_stable_radius && unstable <= rule.max_unstable_share && d.long_run_stable.size() >= 2) {
    out.kind = AnswerKind::steady_state;
    out.draws_summarised = static_cast<int>(d.long_run_stable.size());
    out.immediate = summarise(d.now_stable, g, coverage);
    out.effect = summarise(d.long_run_stable, g, coverage);
    out.reason = fmt("the model settles: spectral radius %.3f <= %.3f", rho, rule.max_stable_radius) + " and " + counts +
                 fmt(" (<= %.0f %%)", 100.0 * rule.max_unstable_share);
    return;
  }
  if (!(rho < 1.0 - 1e-9) && unstable > rule.refuse_unstable_share) {
    out.reason = fmt("the model is past a unit root (spectral radius %.3f >= 1) and ", rho) + counts +
                 fmt(" (> %.0f %%): the levels trend, no effect of an intervention can be predicted",
                     100.0 * rule.refuse_unstable_share);
    return;
  }
  out.kind = AnswerKind::horizon;
  out.horizon_snapshots = h;
  out.draws_summarised = static_cast<int>(d.horizon_all.size());
  out.immediate = summarise(d.now_all, g, coverage);
  out.effect = summarise(d.horizon_all, g, coverage);
  out.reason = fmt("no reliable steady state (spectral radius %.3f, ", rho) + counts + "): effect after " +
               std::to_string(h) + " snapshots";
}

void validate_options(const AnswerRule& rule, const UncertaintyOptions& options) {
  validate_rule(rule);
  if (!(options.coverage > 0.0 && options.coverage < 1.0)) throw std::invalid_argument("answer: coverage must be in (0, 1)");
  if (options.draws < 2) throw std::invalid_argument("answer: need at least 2 Monte Carlo draws");
}

}  // namespace

const char* to_string(AnswerKind kind) {
  static constexpr auto kNames = io::enum_names<AnswerKind>(
      {{AnswerKind::steady_state, "steady_state"}, {AnswerKind::horizon, "horizon"}, {AnswerKind::refused, "refused"}});
  return kNames.name(kind, "unknown");
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

std::vector<BoundedAnswer> answer_interventions(const estimation::SvarLayout& layout, const FactorPosterior& posterior,
                                               const std::vector<InterventionQuery>& queries, const AnswerRule& rule,
                                               const UncertaintyOptions& options, DrawSharing sharing) {
  validate_options(rule, options);
  validate_posterior(layout, posterior);
  const Eigen::Index g = layout.channels();
  const int h = rule.horizon_snapshots;
  const StructuralModel point_model = assemble_structural_model(layout, posterior.mean);
  const double own = own_radius(point_model);
  std::vector<BoundedAnswer> out(queries.size());
  std::vector<QueryDraws> draws(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    draws[i].open = start_answer(point_model, own, queries[i], g, options.coverage, out[i]);
  }
  if (sharing == DrawSharing::shared) {
    // Common random numbers: every query sees the same posterior draws (the same seed gave them the same draws
    // one query at a time too), so each draw is sampled, assembled and checked for settling once.
    detail::PosteriorSampler sampler(layout, posterior, options.seed);
    for (int n = 0; n < options.draws; ++n) {
      const StructuralModel model = assemble_structural_model(layout, sampler.next());
      const bool model_settles = detail::settles(model);
      for (std::size_t i = 0; i < queries.size(); ++i) {
        if (draws[i].open) add_draw(evaluate(model, queries[i], h, model_settles), out[i], draws[i]);
      }
    }
  } else {
    for (std::size_t i = 0; i < queries.size(); ++i) {
      if (!draws[i].open) continue;
      detail::PosteriorSampler sampler(layout, posterior, options.seed);
      for (int n = 0; n < options.draws; ++n) {
        add_draw(evaluate(assemble_structural_model(layout, sampler.next()), queries[i], h, std::nullopt), out[i], draws[i]);
      }
    }
  }
  for (std::size_t i = 0; i < queries.size(); ++i) {
    if (draws[i].open) finish_answer(draws[i], rule, g, options.coverage, out[i]);
  }
  return out;
}

BoundedAnswer answer_intervention(const estimation::SvarLayout& layout, const FactorPosterior& posterior,
                                  const InterventionQuery& query, const AnswerRule& rule,
                                  const UncertaintyOptions& options) {
  return answer_interventions(layout, posterior, {query}, rule, options).front();
}

}  // namespace causal::analysis
