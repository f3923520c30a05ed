// 4. Causal graph snapshots: who drives whom at a few moments of the run (healthy, degrading, end), from
// the recorded condition-level filter factors. The channels sit on a circle; an arrow j -> k is drawn for
// every cross factor x_kj / xL_kj whose estimate is at least min_z standard deviations from zero at that
// moment: solid for instantaneous links, dashed for lagged ones, width growing with |value|, blue when
// positive and red when negative, labelled with the value. Self lags are listed under their channel.
// Pure text generation, no processes (like gnuplot_plots.hpp).
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

// The figure: one panel per moment.
std::string causal_graph_script(const std::string& asset, const std::vector<std::string>& channel_names,
                                const FactorSeries& series, const std::vector<GraphMoment>& moments, double min_z,
                                const PlotStyle& style, const std::string& png_path);

}  // namespace causal::report
