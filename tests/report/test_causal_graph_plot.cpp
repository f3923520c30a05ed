// The causal-graph figure (tools/causal_report/causal_graph_plot.cpp): which factors become arrows (only
// cross factors at least min_z sd from 0, with the right direction and lag), which samples are shown, and
// what the Graphviz graph draws for them.
#include "causal_graph_plot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace causal::report;

namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

// G = 3, five samples one hour apart. Sample 4: x12 = +0.5 (sd 0.1, z 5), x13 = 0.05 (z 0.5), xL11 = 0.9
// (self lag), xL21 = -0.4 (sd 0.1, z 4), x32 = NaN. Samples 0..3: everything within 1 sd of 0.
FactorSeries series() {
  FactorSeries f;
  f.kind = "filter";
  f.outcome_names = {"Bearing 1", "Bearing 2", "Bearing 3"};
  for (int i = 0; i < 5; ++i) f.t.push_back(1.0e9 + 3600.0 * i);
  f.names = {"x12", "x13", "xL11", "xL21", "x32"};
  f.outcome = {0, 0, 0, 1, 2};
  const double last_mean[] = {0.5, 0.05, 0.9, -0.4, NAN};
  for (std::size_t k = 0; k < f.names.size(); ++k) {
    f.mean.push_back({0.01, -0.02, 0.03, 0.0, last_mean[k]});
    f.sd.push_back({0.1, 0.1, 0.1, 0.1, 0.1});
  }
  return f;
}

AlarmSpan alarm_at(double t) {
  AlarmSpan a;
  a.alarm_id = "g/1/feature_drift/1";
  a.channel = 1;
  a.raised = t;
  return a;
}

TEST(CausalGraphPlot, OnlySignificantCrossFactorsBecomeArrows) {
  const FactorSeries f = series();
  const auto edges = significant_edges(f, 4, 2.0);
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_EQ(edges[0].name, "x12");
  EXPECT_EQ(edges[0].from, 1);  // Bearing 2 drives Bearing 1 at once
  EXPECT_EQ(edges[0].to, 0);
  EXPECT_EQ(edges[0].lag, 0);
  EXPECT_DOUBLE_EQ(edges[0].value, 0.5);
  EXPECT_EQ(edges[1].name, "xL21");
  EXPECT_EQ(edges[1].from, 0);  // Bearing 1's previous value drives Bearing 2
  EXPECT_EQ(edges[1].to, 1);
  EXPECT_EQ(edges[1].lag, 1);
  EXPECT_TRUE(significant_edges(f, 2, 2.0).empty());
  EXPECT_EQ(significant_edges(f, 4, 0.4).size(), 3u);  // x13 (z 0.5) joins; the self lag and NaN never do
  EXPECT_TRUE(significant_edges(f, 99, 2.0).empty());   // out of range: nothing, no crash
}

TEST(CausalGraphPlot, SampleAtIsTheLastSampleNotAfterT) {
  const FactorSeries f = series();
  EXPECT_EQ(sample_at(f, 0.0), 0u);
  EXPECT_EQ(sample_at(f, f.t[2]), 2u);
  EXPECT_EQ(sample_at(f, f.t[2] + 10.0), 2u);
  EXPECT_EQ(sample_at(f, 1e12), 4u);
}

TEST(CausalGraphPlot, MomentsAreHealthyHalfwayAndEnd) {
  const FactorSeries f = series();
  // First raise at sample 1: healthy = sample 0, halfway from t[1] to t[4] = sample 2, end = 4.
  const auto m = graph_moments(f, {alarm_at(f.t[1]), alarm_at(f.t[3])});
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].sample, 0u);
  EXPECT_EQ(m[1].sample, 2u);
  EXPECT_EQ(m[2].sample, 4u);
  EXPECT_EQ(m[2].label, "end of run");
  // No alarms: a third into the run and the end.
  const auto quiet = graph_moments(f, {});
  ASSERT_EQ(quiet.size(), 2u);
  EXPECT_EQ(quiet[0].sample, 1u);
  EXPECT_EQ(quiet[1].sample, 4u);
  // An alarm on the last sample: healthy = 3, halfway = end = 4, merged into one panel.
  const auto late = graph_moments(f, {alarm_at(f.t[4])});
  ASSERT_EQ(late.size(), 2u);
  EXPECT_EQ(late[0].sample, 3u);
  EXPECT_EQ(late[1].sample, 4u);
  EXPECT_NE(late[1].label.find("end of run"), std::string::npos);
  EXPECT_TRUE(graph_moments(FactorSeries{}, {}).empty());
}

TEST(CausalGraphPlot, DotGraphHasOneClusterPerMomentAndOneEdgePerLink) {
  const FactorSeries f = series();
  const std::vector<GraphMoment> moments = {{"healthy", 1}, {"end of run", 4}};
  const std::string s = causal_graph_dot("shaft", f.outcome_names, f, moments, 2.0);
  EXPECT_EQ(s.rfind("digraph causal_graph {", 0), 0u);
  EXPECT_EQ(count(s, "subgraph cluster_"), 2u);
  // End of run: x12 positive, instantaneous: solid blue 2 -> 1; xL21 negative, lagged: dashed red 1 -> 2.
  EXPECT_NE(s.find("m1c1 -> m1c0 [color=\"#1f77b4\", fontcolor=\"#1f77b4\", style=solid, penwidth=3.00, "
                   "label=\"x12 +0.50\"]"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("m1c0 -> m1c1 [color=\"#d62728\", fontcolor=\"#d62728\", style=dashed, penwidth=2.60, "
                   "label=\"xL21 -0.40\"]"),
            std::string::npos);
  EXPECT_NE(s.find("label=\"Bearing 1\\nself xL11 +0.90\"]"), std::string::npos);
  // Healthy: nothing at 2 sd, so the three strongest links (all |z| = 0.2, kept in factor order) are grey dotted.
  EXPECT_NE(s.find("healthy\\n"), std::string::npos);
  EXPECT_NE(s.find("\\nno link at 2 sd"), std::string::npos);
  EXPECT_EQ(count(s, "style=dotted"), 3u);
  EXPECT_NE(s.find("m0c1 -> m0c0 [color=\"#999999\""), std::string::npos);
  EXPECT_NE(s.find("label=\"x12 -0.02 (z 0.2)\""), std::string::npos);
  EXPECT_EQ(count(s, " -> m1c"), 2u);  // only the two significant links at the end
  EXPECT_EQ(count(s, "[label=\"Bearing 3"), 2u);  // three channels in each cluster
}

TEST(CausalGraphPlot, DotQuoteEscapes) {
  EXPECT_EQ(dot_quote("a\"b\\c\nd"), "\"a\\\"b\\\\c\\nd\"");
}

}  // namespace
