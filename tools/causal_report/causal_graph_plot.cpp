#include "causal_graph_plot.hpp"

#include "causal/io/time_format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace causal::report {

namespace {

constexpr const char* kPositive = "#1f77b4";
constexpr const char* kNegative = "#d62728";

std::string fixed(double v, const char* fmt) {
  char buf[48];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

std::string utc(double t) { return causal::io::format_utc(static_cast<std::int64_t>(std::llround(t * 1e9))); }

}  // namespace

std::size_t sample_at(const FactorSeries& series, double t) {
  const auto it = std::upper_bound(series.t.begin(), series.t.end(), t);
  return it == series.t.begin() ? 0 : static_cast<std::size_t>(it - series.t.begin()) - 1;
}

std::vector<GraphMoment> graph_moments(const FactorSeries& series, const std::vector<AlarmSpan>& alarms) {
  std::vector<GraphMoment> out;
  if (series.t.empty()) return out;
  const std::size_t last = series.t.size() - 1;
  double first_raise = INFINITY;
  for (const auto& a : alarms) first_raise = std::min(first_raise, a.raised);
  std::vector<GraphMoment> wanted;
  if (std::isfinite(first_raise)) {
    // The graph changes after the change began, not at the first alarm: show it halfway to the end.
    const std::size_t at = sample_at(series, first_raise);
    wanted.push_back({"healthy (before the first alarm)", series.t[at] >= first_raise && at > 0 ? at - 1 : at});
    wanted.push_back({"halfway from the first alarm to the end", sample_at(series, 0.5 * (first_raise + series.t[last]))});
  } else {
    wanted.push_back({"healthy", last / 3});
  }
  wanted.push_back({"end of run", last});
  for (const auto& m : wanted) {
    if (!out.empty() && out.back().sample == m.sample) {
      out.back().label += ", " + m.label;
      continue;
    }
    out.push_back(m);
  }
  return out;
}

std::vector<GraphEdge> significant_edges(const FactorSeries& series, std::size_t sample, double min_z) {
  std::vector<GraphEdge> out;
  const int g = static_cast<int>(series.outcome_names.size());
  for (std::size_t f = 0; f < series.names.size(); ++f) {
    const auto name = parse_factor_name(series.names[f], g);
    if (!name || name->source == name->outcome) continue;  // self lags are not arrows
    if (sample >= series.mean[f].size() || sample >= series.sd[f].size()) continue;
    const double v = series.mean[f][sample], sd = series.sd[f][sample];
    if (!std::isfinite(v) || !std::isfinite(sd) || std::abs(v) < min_z * sd) continue;
    out.push_back({name->source - 1, name->outcome - 1, name->lag, v, sd, series.names[f]});
  }
  return out;
}

std::vector<GraphEdge> strongest_edges(const FactorSeries& series, std::size_t sample, std::size_t count) {
  std::vector<GraphEdge> all = significant_edges(series, sample, 0.0);
  std::stable_sort(all.begin(), all.end(), [](const GraphEdge& a, const GraphEdge& b) {
    return std::abs(a.value) / std::max(a.sd, 1e-300) > std::abs(b.value) / std::max(b.sd, 1e-300);
  });
  if (all.size() > count) all.resize(count);
  return all;
}

std::string dot_quote(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string causal_graph_dot(const std::string& asset, const std::vector<std::string>& channel_names,
                             const FactorSeries& series, const std::vector<GraphMoment>& moments, double min_z) {
  const int g = static_cast<int>(channel_names.size());
  std::ostringstream s;
  // dot lays out each moment as its own cluster; disconnected clusters are packed side by side, and dot places
  // edge labels as layout objects of their own, so labels never overlap each other or the nodes.
  s << "digraph causal_graph {\n"
    << "  graph [fontname=\"DejaVu Sans\", fontsize=16, labelloc=t, nodesep=0.6, ranksep=0.9, newrank=true, "
       "dpi=110, pad=0.3, label="
    << dot_quote("Causal graph of " + asset + ": arrow j -> k where factor x_kj is at least " + fixed(min_z, "%.3g") +
                 " sd from 0\nsolid: at once, dashed: lagged; blue +, red -; width ~ |value|; grey dotted: the "
                 "strongest links when none is significant")
    << "];\n  node [shape=ellipse, style=filled, fillcolor=\"#eeeeee\", color=\"#555555\", fontname=\"DejaVu Sans\", "
       "fontsize=12];\n  edge [fontname=\"DejaVu Sans\", fontsize=10];\n";
  for (std::size_t m = 0; m < moments.size(); ++m) {
    const GraphMoment& mo = moments[m];
    const double t = mo.sample < series.t.size() ? series.t[mo.sample] : NAN;
    std::vector<GraphEdge> edges = significant_edges(series, mo.sample, min_z);
    const bool weak = edges.empty();
    if (weak) edges = strongest_edges(series, mo.sample, 3);
    std::string title = mo.label + "\n" + (std::isfinite(t) ? utc(t) : std::string("?"));
    if (weak) title += "\nno link at " + fixed(min_z, "%.3g") + " sd";
    s << "  subgraph cluster_" << m << " {\n    label=" << dot_quote(title)
      << "; fontsize=13; color=\"#cccccc\"; style=rounded;\n";
    // Self lags (a channel's own persistence) go into the node: they are not arrows between channels.
    std::map<int, std::string> self;
    for (std::size_t f = 0; f < series.names.size(); ++f) {
      const auto name = parse_factor_name(series.names[f], g);
      if (!name || name->source != name->outcome || mo.sample >= series.mean[f].size()) continue;
      const double v = series.mean[f][mo.sample];
      if (std::isfinite(v)) self[name->outcome - 1] += "\nself " + series.names[f] + " " + fixed(v, "%+.2f");
    }
    for (int c = 0; c < g; ++c) {
      s << "    m" << m << "c" << c << " [label=" << dot_quote(channel_names[static_cast<std::size_t>(c)] + self[c])
        << "];\n";
    }
    for (const GraphEdge& e : edges) {
      if (e.from >= g || e.to >= g) continue;
      const double z = std::abs(e.value) / std::max(e.sd, 1e-300);
      const std::string colour = weak ? "#999999" : (e.value >= 0.0 ? kPositive : kNegative);
      const std::string style = weak ? "dotted" : (e.lag == 0 ? "solid" : "dashed");
      const double width = weak ? 1.0 : 1.0 + 4.0 * std::min(std::abs(e.value), 1.0);
      s << "    m" << m << "c" << e.from << " -> m" << m << "c" << e.to << " [color=\"" << colour << "\", fontcolor=\""
        << colour << "\", style=" << style << ", penwidth=" << fixed(width, "%.2f")
        << ", label=" << dot_quote(e.name + " " + fixed(e.value, "%+.2f") + (weak ? " (z " + fixed(z, "%.1f") + ")" : ""))
        << "];\n";
    }
    s << "  }\n";
  }
  s << "}\n";
  return s.str();
}

}  // namespace causal::report
