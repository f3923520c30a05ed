#include "causal_graph_plot.hpp"

#include "causal/io/time_format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace causal::report {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNodeRadius = 0.25;
constexpr const char* kPositive = "#1f77b4";
constexpr const char* kNegative = "#d62728";

std::string fixed(double v, const char* fmt) {
  char buf[48];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

struct Point {
  double x, y;
};

// Channel c of g on the unit circle, the first at the top, clockwise.
Point node(int c, int g) {
  const double a = kPi / 2.0 - 2.0 * kPi * c / std::max(g, 1);
  return {std::cos(a), std::sin(a)};
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

std::string causal_graph_script(const std::string& asset, const std::vector<std::string>& channel_names,
                                const FactorSeries& series, const std::vector<GraphMoment>& moments, double min_z,
                                const PlotStyle& style, const std::string& png_path) {
  const int g = static_cast<int>(channel_names.size());
  const int panels = std::max<int>(1, static_cast<int>(moments.size()));
  std::ostringstream s;
  s << gnuplot_preamble(style, style.width / panels + 90, png_path);  // square panels under a title
  s << "set multiplot layout 1," << panels << " title "
    << gnuplot_quote("Causal graph of " + asset + ": arrow j -> k where factor x_kj is at least " + fixed(min_z, "%.3g") +
                     " sd from 0 (solid: at once, dashed: lagged; blue +, red -; width ~ |value|)")
    << "\n";
  s << "unset border\nunset tics\nunset key\nset size ratio -1\nset xrange [-2.0:2.0]\nset yrange [-1.6:1.6]\n";
  for (const GraphMoment& m : moments) {
    s << "unset arrow\nunset label\nunset object\n";
    const double t = m.sample < series.t.size() ? series.t[m.sample] : NAN;
    s << "set title " << gnuplot_quote(m.label + " (" + (std::isfinite(t) ? utc(t) : std::string("?")) + ")") << "\n";
    // Self lags (a channel's own persistence) as text under its name.
    std::map<int, std::string> self;
    for (std::size_t f = 0; f < series.names.size(); ++f) {
      const auto name = parse_factor_name(series.names[f], g);
      if (!name || name->source != name->outcome || m.sample >= series.mean[f].size()) continue;
      const double v = series.mean[f][m.sample];
      if (std::isfinite(v)) self[name->outcome - 1] += " " + series.names[f] + " " + fixed(v, "%+.2f");
    }
    int object = 1;
    for (int c = 0; c < g; ++c) {
      const Point p = node(c, g);
      s << "set object " << object++ << " circle at " << fixed(p.x, "%.4f") << "," << fixed(p.y, "%.4f") << " size "
        << kNodeRadius << " fc rgb '#eeeeee' fs solid border lc rgb '#555555' front\n";
      s << "set label " << gnuplot_quote(channel_names[static_cast<std::size_t>(c)]) << " at " << fixed(p.x, "%.4f")
        << "," << fixed(p.y, "%.4f") << " center front font ',9'\n";
      if (self.count(c)) {  // outside the circle of channels, where no arrow runs
        const double gap = kNodeRadius + 0.06;
        const char* just = p.x > 0.3 ? "left" : p.x < -0.3 ? "right" : "center";
        const double lx = p.x > 0.3 ? p.x + gap : p.x < -0.3 ? p.x - gap : p.x;
        const double ly = std::abs(p.x) > 0.3 ? p.y : p.y + (p.y >= 0.0 ? gap + 0.04 : -gap - 0.04);
        s << "set label " << gnuplot_quote("self:" + self[c]) << " at " << fixed(lx, "%.4f") << "," << fixed(ly, "%.4f")
          << " " << just << " front font ',8' tc rgb '#555555'\n";
      }
    }
    for (const GraphEdge& e : significant_edges(series, m.sample, min_z)) {
      if (e.from >= g || e.to >= g) continue;
      const Point a = node(e.from, g), b = node(e.to, g);
      const double dx = b.x - a.x, dy = b.y - a.y, len = std::hypot(dx, dy);
      if (len <= 0.0) continue;
      const double ux = dx / len, uy = dy / len;
      // Offset to the left of the direction of travel: j -> k and k -> j, and the instantaneous and lagged
      // links of one pair, never overlap.
      const double off = 0.05 + 0.07 * e.lag;
      const double ox = -uy * off, oy = ux * off;
      const Point from{a.x + ux * kNodeRadius + ox, a.y + uy * kNodeRadius + oy};
      const Point to{b.x - ux * kNodeRadius + ox, b.y - uy * kNodeRadius + oy};
      const double width = 1.0 + 4.0 * std::min(std::abs(e.value), 1.0);
      s << "set arrow from " << fixed(from.x, "%.4f") << "," << fixed(from.y, "%.4f") << " to " << fixed(to.x, "%.4f")
        << "," << fixed(to.y, "%.4f") << " head filled size 0.08,20 lw " << fixed(width, "%.2f") << " dt "
        << (e.lag == 0 ? 1 : 2) << " lc rgb '" << (e.value >= 0.0 ? kPositive : kNegative) << "' front\n";
      // A third of the way along: the labels of j -> k and k -> j land at different places.
      const Point mid{from.x + (to.x - from.x) / 3.0 + ox, from.y + (to.y - from.y) / 3.0 + oy};
      s << "set label " << gnuplot_quote(e.name + " " + fixed(e.value, "%+.2f")) << " at " << fixed(mid.x, "%.4f")
        << "," << fixed(mid.y, "%.4f") << " center front font ',8' tc rgb '"
        << (e.value >= 0.0 ? kPositive : kNegative) << "'\n";
    }
    s << "plot NaN notitle\n";
  }
  s << "unset multiplot\n";
  return s.str();
}

}  // namespace causal::report
