// gnuplot scripts for the three report figures. Each script is self-contained (data inline as
// datablocks), so it can be re-run by hand: gnuplot <name>.gp. Pure text generation, no processes.
#pragma once

#include "run_data.hpp"

#include <string>
#include <vector>

namespace causal::report {

struct PlotStyle {
  bool pngcairo = true;  // else gnuplot's libgd "png" terminal
  int width = 1400, height = 900;
};

// gnuplot single-quoted string literal (quotes doubled).
std::string gnuplot_quote(const std::string& text);

// Terminal (PNG, width x height) and output file lines that start every figure script.
std::string gnuplot_preamble(const PlotStyle& style, int height, const std::string& png);

// Time span shown on every figure of an asset, seconds since the epoch.
struct TimeRange {
  double from = 0.0, to = 0.0;
  bool valid() const { return to > from; }
};

// 1. Condition feature per channel vs time (log y when every value is > 0); alarm raise and escalation
//    times as vertical lines coloured by severity. One panel per recorded feature.
std::string condition_trends_script(const std::string& asset, const std::vector<ConditionSeries>& features,
                                    const std::vector<AlarmSpan>& alarms, const TimeRange& range,
                                    const PlotStyle& style, const std::string& png_path);

// 2. Factor trajectories of one outcome: one panel per factor (factor_indices into the series), filter
//    and, when given, fixed-lag smoother with +-2 sd bands; alarms on the outcome channel as lines.
//    filter or fixed_lag may be null (not both). channel_names name the source channels in titles.
std::string factor_panels_script(const std::string& asset, const std::string& outcome_name,
                                 const FactorSeries* filter, const FactorSeries* fixed_lag,
                                 const std::vector<std::size_t>& factor_indices,
                                 const std::vector<std::string>& channel_names, const std::vector<AlarmSpan>& alarms,
                                 int outcome_channel, const TimeRange& range, const PlotStyle& style,
                                 const std::string& png_path, const std::string& page_note);

// 3. Alarm timeline: one row per channel, bars from raised to cleared (or the end) coloured by severity
//    (escalations change the colour), labelled with the detector kind and the root cause.
std::string alarm_timeline_script(const std::string& asset, const std::vector<std::string>& channel_names,
                                  const std::vector<AlarmSpan>& alarms, const TimeRange& range,
                                  const PlotStyle& style, const std::string& png_path);

// "Bearing 2 -> Bearing 1" style title of a factor: "xL12: Bearing 2 (lag 1) -> Bearing 1".
std::string factor_title(const std::string& name, const std::vector<std::string>& channel_names);

}  // namespace causal::report
