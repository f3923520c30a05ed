#include "whatif_output.hpp"

#include <causal/analysis/effect_units.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace causal::whatif {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// Shortest text that reads back to the same double (for the CSV).
std::string exact(double v) {
  char buf[40];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

std::string pad(const std::string& s, std::size_t width) {
  return s.size() >= width ? s + " " : s + std::string(width - s.size(), ' ');
}

std::string join_order(const std::vector<int>& order, const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < order.size(); ++i) s += (i ? " -> " : "") + names[static_cast<std::size_t>(order[i])];
  return s;
}

}  // namespace

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

void print_model_summary(std::ostream& out, const FittedModel& m) {
  const estimation::SvarLayout& layout = *m.layout;
  out << "model: " << layout.channels() << " channels, " << m.centered.rows() << " rows, lag order " << layout.lag_order()
      << ", self lags " << (m.spec.include_self_lags ? "on" : "off") << ", " << layout.total_factors() << " factors\n";
  const std::string window = "rows 0.." + std::to_string(m.calibration_rows - 1);
  if (m.lingam) {
    out << "instantaneous links: VAR-LiNGAM causal order (estimated on " << window << "): " << join_order(m.order, m.names)
        << "\n";
  } else if (!m.order.empty()) {
    out << "instantaneous links: configured acyclic graph, a causal order: " << join_order(m.order, m.names) << "\n";
  } else {
    out << "instantaneous links: UNRESTRICTED (both directions). The per-outcome regressions are then not one identified\n"
           "  structural model: effects below may be non-causal or fail as not identifiable. Use --lingam or --graph.\n";
  }
  out << "noise: " << (m.noise_tuned ? "tuned per outcome by innovation likelihood on " + window : std::string("as given"))
      << " (q, r):";
  for (std::size_t k = 0; k < m.noise.size(); ++k) out << " " << m.names[k] << " (" << num(m.noise[k].q) << ", " << num(m.noise[k].r) << ")";
  out << "\n";
  out << "filter: " << m.run.counters.updated << " samples used, " << m.run.counters.rejected_non_finite
      << " rejected (non-finite), " << m.run.counters.warm_up << " warm-up\n";
  out << "snapshot: filtered factors at row " << m.at << "; ";
  if (m.dynamics.status == analysis::AnalysisStatus::ok) {
    out << "companion spectral radius " << num(m.dynamics.spectral_radius) << "\n";
  } else {
    out << analysis::to_string(m.dynamics.status) << ": " << m.dynamics.message << "\n";
  }
}

void print_intervention(std::ostream& out, const FittedModel& m, const analysis::InterventionQuery& q,
                        const analysis::UncertainEffect& u, const analysis::BoundedAnswer& answer,
                        const analysis::UncertaintyOptions& opt) {
  const bool impulse = q.kind == analysis::InterventionKind::impulse;
  const std::string& name = m.names[static_cast<std::size_t>(q.channel)];
  out << "\nintervention: do(" << name << " := " << name << (q.delta < 0 ? " - " : " + ") << num(std::abs(q.delta)) << ") "
      << (impulse ? "for one sample (impulse)" : "sustained from now on") << "\n";
  if (u.point.status != analysis::AnalysisStatus::ok) {
    out << "status: " << analysis::to_string(u.point.status) << ": " << u.point.message << "\n";
  }
  char pct[16];
  std::snprintf(pct, sizeof pct, "%g%%", 100.0 * u.coverage);
  if (u.interval_valid) {
    out << "intervals: " << pct << " central, ";
    if (u.method == analysis::IntervalMethod::monte_carlo) {
      out << "Monte Carlo over " << opt.draws << " draws of the factor posterior (seed " << opt.seed << "), "
          << u.draws_rejected << " draws rejected (intervened system singular or not settling)\n";
    } else {
      out << "delta method (first order, normal)\n";
    }
  } else if (u.point.status == analysis::AnalysisStatus::ok) {
    out << "intervals: unavailable (too few usable draws / perturbations at the edge of stability)\n";
  }
  const std::size_t w = std::max<std::size_t>(12, [&] {
    std::size_t mx = 0;
    for (const auto& s : m.names) mx = std::max(mx, s.size() + 2);
    return mx;
  }());
  const bool mc = u.method == analysis::IntervalMethod::monte_carlo;
  if (mc) {  // the live twin's numbers: medians and quantiles of the same draws (bounded_answer.hpp)
    if (!answer.answered()) {
      out << "no table: the bounded answer is refused (below)\n";
      return;
    }
    const std::string label = answer.kind == analysis::AnswerKind::steady_state
                                  ? (impulse ? "cumulative" : "steady_state")
                                  : "after_" + std::to_string(answer.horizon_snapshots);
    out << "(medians of the " << answer.draws_summarised << " summarised draws; the same draws give the intervals)\n";
    out << pad("channel", w) << pad("immediate", 13) << pad("lower", 13) << pad("upper", 13) << pad(label, 13)
        << pad("lower", 13) << "upper\n";
    for (int k = 0; k < static_cast<int>(m.names.size()); ++k) {
      out << pad(m.names[static_cast<std::size_t>(k)], w) << pad(num(answer.immediate.median(k)), 13)
          << pad(num(answer.immediate.lower(k)), 13) << pad(num(answer.immediate.upper(k)), 13)
          << pad(num(answer.effect.median(k)), 13) << pad(num(answer.effect.lower(k)), 13) << num(answer.effect.upper(k))
          << "\n";
    }
  } else {
    out << pad("channel", w) << pad("immediate", 13) << pad("lower", 13) << pad("upper", 13)
        << pad(impulse ? "cumulative" : "steady_state", 13) << pad("lower", 13) << "upper\n";
    const auto& sum = impulse ? u.point.cumulative : u.point.steady_state;
    const auto& sum_i = impulse ? u.cumulative : u.steady_state;
    for (int k = 0; k < static_cast<int>(m.names.size()); ++k) {
      out << pad(m.names[static_cast<std::size_t>(k)], w) << pad(num(u.point.immediate(k)), 13)
          << pad(num(u.immediate.lower(k)), 13) << pad(num(u.immediate.upper(k)), 13) << pad(num(sum(k)), 13)
          << pad(num(sum_i.lower(k)), 13) << num(sum_i.upper(k)) << "\n";
    }
  }
  if (impulse) out << "(an impulse leaves no steady-state change when the system is stable; 'cumulative' = sum over all samples)\n";
}

void print_bounded_answer(std::ostream& out, const FittedModel& m, const analysis::InterventionQuery& q,
                          const analysis::BoundedAnswer& a, bool log_levels) {
  out << "\nanswer (" << analysis::to_string(a.kind) << "): " << a.reason << "\n";
  if (!a.answered()) return;
  analysis::EffectUnits units;
  units.log_level = log_levels;
  for (int k = 0; k < static_cast<int>(m.names.size()); ++k) {
    if (k == q.channel) continue;
    // The level the percent refers to: the raw value at the model's row (unused for log levels).
    const double level = m.raw(m.at, k);
    const bool percent = log_levels || (level > 0.0 && std::isfinite(level));
    out << "  " << m.names[static_cast<std::size_t>(k)] << " ";
    if (percent) {  // the live twin's line, with its "effect unknown" rule
      out << analysis::answer_line(a, k, level, units);
    } else {  // no positive level to state a percent of: the same "unknown", with the reason
      const std::string when = a.kind == analysis::AnswerKind::steady_state
                                   ? std::string("at steady state")
                                   : "after " + std::to_string(a.horizon_snapshots) + " samples";
      char tail[240];
      std::snprintf(tail, sizeof tail,
                    ": effect unknown (the level at row %d is not positive, so no percent of it can be stated; "
                    "--log-levels if the CSV holds log levels), model %s rho=%.3f, %d/%d draws unstable",
                    m.at, analysis::stability_words(a), a.spectral_radius, a.unstable_draws, a.draws);
      out << when << tail;
    }
    out << " (" << num(a.effect.median(k)) << " [" << num(a.effect.lower(k)) << ", " << num(a.effect.upper(k))
        << "] in the CSV's units)\n";
  }
}

void write_counterfactual_csv(std::ostream& out, const std::vector<std::string>& names, int from,
                              const Eigen::MatrixXd& counterfactual, const Eigen::MatrixXd& observed) {
  out << "n";
  for (const auto& name : names) out << "," << csv_field(name);
  for (const auto& name : names) out << "," << csv_field(name + " (observed)");
  out << "\n";
  for (Eigen::Index i = 0; i < counterfactual.rows(); ++i) {
    out << (from + i);
    for (Eigen::Index k = 0; k < counterfactual.cols(); ++k) out << "," << exact(counterfactual(i, k));
    for (Eigen::Index k = 0; k < observed.cols(); ++k) out << "," << exact(observed(i, k));
    out << "\n";
  }
}

void print_recommendations(std::ostream& out, const FittedModel& m, int target,
                           const std::vector<analysis::Recommendation>& recs) {
  out << "\nrecommendations for " << m.names[static_cast<std::size_t>(target)]
      << " (ranked by the interval bound in the helpful direction: the reduction we are sure of first):\n";
  if (recs.empty()) {
    out << "  none: no other channel is above its baseline, so there is nothing to reduce.\n";
    return;
  }
  int rank = 1;
  for (const auto& r : recs) out << "  " << rank++ << ". " << r.text << "\n";
}

}  // namespace causal::whatif
