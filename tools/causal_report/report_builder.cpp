#include "report_builder.hpp"

#include "causal/config/exit_codes.hpp"

#include "causal/io/csv_format.hpp"
#include "causal/io/file_names.hpp"
#include "causal_graph_plot.hpp"
#include "gnuplot_plots.hpp"
#include "process.hpp"
#include "verdict.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace causal::report {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kPanelsPerPage = 12;
// A causal-graph arrow needs its factor at least this many standard deviations from 0 (about 95 % two-sided).
constexpr double kGraphMinZ = 2.0;

std::string tail_of(const fs::path& log, std::size_t max_chars = 600) {
  std::ifstream in(log);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  if (text.size() > max_chars) text = "..." + text.substr(text.size() - max_chars);
  return text;
}

struct Renderer {
  fs::path gnuplot;
  std::optional<fs::path> dot;  // Graphviz, for the causal graph; the figure is skipped (and said so) without it
  fs::path out_dir;
  PlotStyle style;
  std::ostream& out;
  std::ostream& err;
  bool failed = false;

  // Writes <stem>.gp under out/gnuplot, runs gnuplot on it, checks the PNG. True when the PNG exists.
  bool render(const std::string& stem, const std::string& script) { return run(stem, ".gp", script, false); }
  // Writes <stem>.dot under out/gnuplot, runs `dot -Tpng` on it, checks the PNG.
  bool render_dot(const std::string& stem, const std::string& graph) { return run(stem, ".dot", graph, true); }

  bool run(const std::string& stem, const char* extension, const std::string& script, bool graphviz) {
    const fs::path gp = out_dir / "gnuplot" / (stem + extension);
    const fs::path log = out_dir / "gnuplot" / (stem + ".log");
    const fs::path png = out_dir / (stem + ".png");
    {
      std::ofstream f(gp);
      f << script;
      if (!f) {
        err << "causal-report: cannot write " << gp.string() << "\n";
        failed = true;
        return false;
      }
    }
    std::error_code ec;
    fs::remove(png, ec);  // a stale PNG must not pass for a fresh one
    const ProcessResult r = graphviz ? run_process({dot->string(), "-Tpng", "-o", png.string(), gp.string()}, log)
                                     : run_process({gnuplot.string(), gp.string()}, log);
    const bool ok = r.started && !r.timed_out && r.exit_code == 0 && fs::exists(png, ec) && fs::file_size(png, ec) > 0;
    if (!ok) {
      err << "causal-report: " << (graphviz ? "dot" : "gnuplot") << " failed on " << gp.string()
          << (r.timed_out ? " (timed out)" : " (exit " + std::to_string(r.exit_code) + ")") << ":\n"
          << tail_of(log) << "\n";
      failed = true;
      return false;
    }
    out << "wrote " << png.string() << "\n";
    return true;
  }
};

TimeRange data_range(const std::vector<ConditionSeries>& conditions, const std::vector<const FactorSeries*>& factors,
                     const std::vector<AlarmRecord>& alarms) {
  double lo = INFINITY, hi = -INFINITY;
  auto take = [&](double t) {
    if (!std::isfinite(t)) return;
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  };
  for (const auto& c : conditions) for (double t : c.t) take(t);
  for (const auto* f : factors) for (double t : f->t) take(t);
  for (const auto& a : alarms) {
    if (a.raised) take(*a.raised);
    if (a.cleared) take(*a.cleared);
    if (a.time) take(*a.time);
  }
  if (!std::isfinite(lo)) return {};
  // A little room on both sides so the first and last points and alarm lines are not on the frame.
  const double pad = hi > lo ? 0.01 * (hi - lo) : 1800.0;
  return {lo - pad, hi + pad};
}

std::vector<RecommendationRecord> recommendations_of(const fs::path& file, const std::string& asset) {
  std::error_code ec;
  return fs::exists(file, ec) ? load_recommendations(file, asset) : std::vector<RecommendationRecord>{};
}

std::vector<PrognosisRecord> prognoses_of(const fs::path& file, const std::string& asset) {
  std::error_code ec;
  return fs::exists(file, ec) ? load_prognoses(file, asset) : std::vector<PrognosisRecord>{};
}

// The verdict and every recommendation (publication order) as Markdown.
std::string verdict_markdown(const std::string& asset, const std::vector<AlarmRecord>& alarms,
                             const fs::path& recommendations_file) {
  const auto recs = recommendations_of(recommendations_file, asset);
  std::ostringstream md;
  const auto prognoses = prognoses_of(recommendations_file.parent_path() / "prognosis.csv", asset);
  md << "\n## Verdict\n\n```\n" << verdict_table({verdict_of(asset, alarms, recs, prognoses)}) << "```\n";
  md << "\n## Recommendations (" << recs.size() << ", in the order they were published)\n\n";
  if (recs.empty()) md << "None recorded.\n";
  for (const auto& r : recs) {
    std::string text = r.text;
    for (char& c : text) if (c == '\n' || c == '|') c = ' ';
    md << "- **" << r.recommendation_id << "** (rank " << r.rank
       << (r.sample_index.empty() ? "" : ", at index " + r.sample_index)
       << (r.action_kind.empty() ? "" : ", " + r.action_kind) << (r.reliable ? "" : ", no reliable lever")
       << "): " << text << "\n";
  }
  return md.str();
}

void render_asset(const AssetFiles& files, const fs::path& alarms_file, const std::string& run_dir, Renderer& r) {
  const std::string& asset = files.asset;
  std::vector<std::string> notes;
  std::vector<ConditionSeries> conditions;
  for (const auto& [feature, path] : files.conditions) {
    auto c = load_conditions(path, feature);
    if (c.t.empty()) notes.push_back(path.filename().string() + " has no rows");
    else conditions.push_back(std::move(c));
  }
  FactorSeries filter, fixed_lag;
  const FactorSeries* pf = nullptr;
  const FactorSeries* pl = nullptr;
  if (!files.factors_filter.empty()) {
    filter = load_factors(files.factors_filter, "filter");
    if (!filter.t.empty() && !filter.names.empty()) pf = &filter;
  }
  if (!files.factors_fixed_lag.empty()) {
    fixed_lag = load_factors(files.factors_fixed_lag, "fixed-lag");
    if (!fixed_lag.t.empty() && !fixed_lag.names.empty()) pl = &fixed_lag;
  }
  const std::vector<AlarmRecord> alarm_rows =
      alarms_file.empty() ? std::vector<AlarmRecord>{} : load_alarms(alarms_file, asset);
  std::vector<const FactorSeries*> factor_list;
  if (pf) factor_list.push_back(pf);
  if (pl) factor_list.push_back(pl);
  const TimeRange range = data_range(conditions, factor_list, alarm_rows);
  if (!range.valid()) {
    r.err << "causal-report: asset '" << asset << "' has no time-stamped rows: nothing to plot\n";
    r.failed = true;
    return;
  }
  // Spans that never cleared run to the last data time (the range without its padding).
  const double end_time = range.to - (range.to - range.from) / 1.02 * 0.01;
  const std::vector<AlarmSpan> spans = build_alarm_spans(alarm_rows, end_time);

  std::vector<std::string> channels;
  if (!conditions.empty()) channels = conditions.front().channels;
  else if (pf || pl) channels = (pf ? pf : pl)->outcome_names;
  for (const auto& a : alarm_rows) {
    if (a.channel < 1) continue;
    if (static_cast<std::size_t>(a.channel) > channels.size()) channels.resize(static_cast<std::size_t>(a.channel));
    if (channels[static_cast<std::size_t>(a.channel - 1)].empty()) channels[static_cast<std::size_t>(a.channel - 1)] = a.channel_name;
  }

  std::vector<std::pair<std::string, std::string>> figures;
  if (!conditions.empty()) {
    const std::string stem = "condition_trends_" + asset;
    if (r.render(stem, condition_trends_script(asset, conditions, spans, range, r.style, (r.out_dir / (stem + ".png")).string()))) {
      figures.emplace_back("Condition trends", stem + ".png");
    }
  } else {
    notes.push_back("no condition vectors recorded: no condition-trend figure");
  }
  if (pf || pl) {
    const FactorSeries* primary = pf ? pf : pl;
    for (std::size_t k = 0; k < primary->outcome_names.size(); ++k) {
      std::vector<std::size_t> idx;
      for (std::size_t f = 0; f < primary->names.size(); ++f) {
        if (primary->outcome[f] == static_cast<int>(k)) idx.push_back(f);
      }
      if (idx.empty()) continue;
      const std::size_t pages = (idx.size() + kPanelsPerPage - 1) / kPanelsPerPage;
      for (std::size_t p = 0; p < pages; ++p) {
        const std::vector<std::size_t> page(idx.begin() + static_cast<long>(p * kPanelsPerPage),
                                            idx.begin() + static_cast<long>(std::min(idx.size(), (p + 1) * kPanelsPerPage)));
        const std::string outcome = primary->outcome_names[k];
        const std::string stem = "factors_" + asset + "_" + io::safe_file_component(outcome) +
                                 (pages > 1 ? "_p" + std::to_string(p + 1) : "");
        const std::string note = pages > 1 ? ", page " + std::to_string(p + 1) + "/" + std::to_string(pages) : "";
        const std::string script = factor_panels_script(asset, outcome, pf, pl, page, primary->outcome_names, spans,
                                                        static_cast<int>(k + 1), range, r.style,
                                                        (r.out_dir / (stem + ".png")).string(), note);
        if (r.render(stem, script)) figures.emplace_back("Causal factors of " + outcome + note, stem + ".png");
      }
    }
  } else {
    notes.push_back("no condition-level factors recorded: no factor figures");
  }
  if (pf != nullptr && !pf->outcome_names.empty() && !r.dot) {
    notes.push_back("Graphviz `dot` not found: no causal-graph figure (Debian: apt-get install graphviz)");
  } else if (pf != nullptr && !pf->outcome_names.empty()) {
    const std::vector<GraphMoment> moments = graph_moments(*pf, spans);
    const std::string stem = "causal_graph_" + asset;
    if (r.render_dot(stem, causal_graph_dot(asset, pf->outcome_names, *pf, moments, kGraphMinZ))) {
      std::string when;
      for (const auto& m : moments) when += (when.empty() ? "" : "; ") + m.label;
      figures.emplace_back("Causal graph (" + when + ")", stem + ".png");
    }
  }
  const std::string stem = "alarm_timeline_" + asset;
  if (r.render(stem, alarm_timeline_script(asset, channels, spans, range, r.style, (r.out_dir / (stem + ".png")).string()))) {
    figures.emplace_back("Alarm timeline", stem + ".png");
  }
  const fs::path md = r.out_dir / ("report_" + asset + ".md");
  std::ofstream f(md);
  f << report_markdown(asset, run_dir, figures, spans, notes);
  f << verdict_markdown(asset, alarm_rows, fs::path(run_dir) / "recommendations.csv");
  if (!f) {
    r.err << "causal-report: cannot write " << md.string() << "\n";
    r.failed = true;
    return;
  }
  r.out << "wrote " << md.string() << "\n";
}

}  // namespace

int build_report(const ReportOptions& options, std::ostream& out, std::ostream& err) {
  const fs::path run(options.run_dir);
  std::error_code ec;
  if (!fs::is_directory(run, ec)) {
    err << "causal-report: run folder '" << options.run_dir << "' does not exist or is not a folder\n";
    return causal::config::kExitUsage;
  }
  RunFiles files;
  try {
    files = discover_run(run);
  } catch (const std::exception& e) {
    err << "causal-report: " << e.what() << "\n";
    return causal::config::kExitUsage;
  }
  if (files.csv_count == 0) {
    err << "causal-report: no recorder CSV files (conditions_*.csv, factors_*.csv, alarms.csv) in '"
        << options.run_dir << "'\n";
    return causal::config::kExitUsage;
  }
  std::vector<const AssetFiles*> selected;
  for (const auto& a : files.assets) {
    if (options.asset.empty() || a.asset == io::safe_file_component(options.asset)) selected.push_back(&a);
  }
  if (selected.empty()) {
    std::string known;
    for (const auto& a : files.assets) known += (known.empty() ? "" : ", ") + a.asset;
    err << "causal-report: asset '" << options.asset << "' is not in '" << options.run_dir << "'"
        << (known.empty() ? std::string(" (no asset data at all)") : " (assets: " + known + ")") << "\n";
    return causal::config::kExitUsage;
  }
  if (options.verdict_only) {
    std::vector<AssetVerdict> verdicts;
    try {
      for (const AssetFiles* a : selected) {
        const auto alarms = files.alarms.empty() ? std::vector<AlarmRecord>{} : load_alarms(files.alarms, a->asset);
        verdicts.push_back(verdict_of(a->asset, alarms, recommendations_of(run / "recommendations.csv", a->asset),
                                      prognoses_of(run / "prognosis.csv", a->asset)));
      }
    } catch (const std::exception& e) {
      err << "causal-report: " << e.what() << "\n";
      return causal::config::kExitUsage;
    }
    out << verdict_table(verdicts);
    return 0;
  }
  const auto gnuplot = find_executable(options.gnuplot);
  if (!gnuplot) {
    err << "causal-report: gnuplot not found ('" << options.gnuplot
        << "' is not an executable on PATH): install gnuplot (Debian: apt-get install gnuplot-nox) or pass "
           "--gnuplot PATH\n";
    return causal::config::kExitUsage;
  }
  const fs::path out_dir(options.out_dir);
  fs::create_directories(out_dir / "gnuplot", ec);
  if (ec) {
    err << "causal-report: cannot create output folder '" << options.out_dir << "': " << ec.message() << "\n";
    return causal::config::kExitUsage;
  }
  Renderer r{*gnuplot, find_executable("dot"), out_dir, PlotStyle{}, out, err};
  if (!r.dot) err << "causal-report: Graphviz 'dot' not found: the causal graph is skipped (apt-get install graphviz)\n";
  // pngcairo draws anti-aliased lines and transparent bands; libgd's png is the fallback.
  const ProcessResult probe =
      run_process({gnuplot->string(), "-e", "set terminal pngcairo"}, out_dir / "gnuplot" / "terminal_probe.log");
  r.style.pngcairo = probe.started && probe.exit_code == 0;
  if (!r.style.pngcairo) out << "gnuplot has no pngcairo terminal: using png\n";
  std::vector<AssetVerdict> verdicts;
  for (const AssetFiles* a : selected) {
    try {
      render_asset(*a, files.alarms, options.run_dir, r);
      const auto alarms = files.alarms.empty() ? std::vector<AlarmRecord>{} : load_alarms(files.alarms, a->asset);
      verdicts.push_back(verdict_of(a->asset, alarms, recommendations_of(run / "recommendations.csv", a->asset),
                                      prognoses_of(run / "prognosis.csv", a->asset)));
    } catch (const std::exception& e) {
      err << "causal-report: asset '" << a->asset << "': " << e.what() << "\n";
      r.failed = true;
    }
  }
  if (!verdicts.empty()) out << "\n=== verdict ===\n" << verdict_table(verdicts);
  return r.failed ? causal::config::kExitFailed : causal::config::kExitOk;
}

}  // namespace causal::report
