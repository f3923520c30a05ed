// 4. Causal graph snapshots: who drives whom at a few moments of the run (healthy, degrading, end), from
// the recorded condition-level filter factors, drawn by Graphviz `dot` (it places edge labels so that they do
// not overlap). An arrow j -> k is drawn for every cross factor x_kj / xL_kj whose estimate is at least min_z
// standard deviations from zero at that moment: solid for instantaneous links, dashed for lagged ones, width
// growing with |value|, blue when positive and red when negative, labelled with the value. A moment without
// any such link shows its three strongest links grey and dotted, with their z, so an empty panel never hides
// what the factors say. Self lags are written in their channel's node. Pure text generation, no processes.
#pragma once

#include "gnuplot_plots.hpp"
#include "run_data.hpp"

#include <string>
#include <vector>

namespace causal::report {

struct GraphMoment {
  std::string label;   // e.g. "healthy", "first alarm"
  std::size_t sample;  // column of the factor series
};

struct GraphEdge {
  int from = 0, to = 0;  // 0-based channels: from drives to
  int lag = 0;           // 0 = instantaneous
  double value = 0.0, sd = 0.0;
  std::string name;      // factor name, e.g. "xL12"
};

// Index of the last sample at or before t (0 when t precedes every sample). series.t must be sorted.
std::size_t sample_at(const FactorSeries& series, double t);

// Up to three moments: the last sample before the first alarm raise as "healthy", the sample halfway from
// the first raise to the end, and the last sample ("end of run"); without alarms a third into the run and
// the end. Moments on the same sample are merged. Empty for an empty series.
std::vector<GraphMoment> graph_moments(const FactorSeries& series, const std::vector<AlarmSpan>& alarms);

// Cross factors of sample `sample` with |value| >= min_z * sd (finite values only); self lags excluded.
std::vector<GraphEdge> significant_edges(const FactorSeries& series, std::size_t sample, double min_z);

// The `strongest` cross factors of `sample` by |value| / sd, largest first (shown when none is significant).
std::vector<GraphEdge> strongest_edges(const FactorSeries& series, std::size_t sample, std::size_t count);

// Quotes a Graphviz string: backslash-escapes quotes and backslashes, newlines become centred line breaks.
std::string dot_quote(const std::string& text);

// The figure as a Graphviz `dot` graph: one cluster per moment, side by side.
std::string causal_graph_dot(const std::string& asset, const std::vector<std::string>& channel_names,
                             const FactorSeries& series, const std::vector<GraphMoment>& moments, double min_z);

}  // namespace causal::report
