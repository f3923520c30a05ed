#include "causal/analysis/causal_graph.hpp"

#include <gtest/gtest.h>

#include <causal/estimation/svar_layout.hpp>

#include <functional>
#include <stdexcept>
#include <string>

using causal::estimation::ModelSpec;
using causal::estimation::SvarLayout;
using causal::analysis::CausalGraph;
using causal::analysis::parse_causal_graph;
using causal::analysis::restrict_to_order;

namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(CausalGraph, AcyclicGraphGivesTopologicalOrderAndMask) {
  CausalGraph graph(4);
  graph.add_edge(2, 0);  // y3 -> y1
  graph.add_edge(0, 1);  // y1 -> y2
  graph.add_edge(2, 3);
  EXPECT_TRUE(graph.is_acyclic());
  const std::vector<int> order = graph.topological_order();
  std::vector<int> pos(4);
  for (int p = 0; p < 4; ++p) pos[order[p]] = p;
  EXPECT_LT(pos[2], pos[0]);
  EXPECT_LT(pos[0], pos[1]);
  EXPECT_LT(pos[2], pos[3]);
  const auto mask = graph.instantaneous_mask();
  EXPECT_TRUE(mask[0][2]);   // [k][j]: 3 -> 1
  EXPECT_FALSE(mask[2][0]);
  EXPECT_EQ(graph.edge_count(), 3);
}

TEST(CausalGraph, CycleIsDetectedAndNamed) {
  CausalGraph graph(3);
  graph.add_edge(0, 1);
  graph.add_edge(1, 2);
  graph.add_edge(2, 0);
  const std::vector<int> cycle = graph.find_cycle();
  ASSERT_EQ(cycle.size(), 3u);
  const std::string msg = message_of([&] { graph.topological_order(); });
  EXPECT_NE(msg.find("cycle"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1 -> 2 -> 3 -> 1"), std::string::npos) << msg;
  causal::estimation::ModelSpec spec;
  spec.channels = 3;
  EXPECT_THROW(graph.apply_to(spec), std::invalid_argument);
  EXPECT_EQ(causal::analysis::describe_cycle(cycle, {"a", "b", "c"}), "a -> b -> c -> a");
}

TEST(CausalGraph, TwoWayLinkIsACycle) {
  CausalGraph graph(2);
  graph.add_edge(0, 1);
  graph.add_edge(1, 0);
  EXPECT_FALSE(graph.is_acyclic());
}

TEST(CausalGraph, BadEdgesThrow) {
  CausalGraph graph(3);
  EXPECT_THROW(graph.add_edge(1, 1), std::invalid_argument);
  EXPECT_THROW(graph.add_edge(0, 3), std::invalid_argument);
  EXPECT_THROW(CausalGraph(0), std::invalid_argument);
}

TEST(CausalGraph, ApplyToSpecBuildsLayoutWithOnlyGraphLinks) {
  CausalGraph graph(3);
  graph.add_edge(0, 1);
  graph.add_edge(1, 2);
  causal::estimation::ModelSpec spec;
  spec.channels = 3;
  spec.lag_order = 1;
  const causal::estimation::SvarLayout layout(graph.apply_to(spec));
  // Outcome 0 (root): no instantaneous factor; outcome 1: y1 only; outcome 2: y2 only.
  EXPECT_EQ(layout.factor_index(0, 1, 0), -1);
  EXPECT_GE(layout.factor_index(1, 0, 0), 0);
  EXPECT_EQ(layout.factor_index(1, 2, 0), -1);
  EXPECT_GE(layout.factor_index(2, 1, 0), 0);
  EXPECT_EQ(layout.factor_index(2, 0, 0), -1);
  // Lagged links are untouched by the instantaneous graph.
  EXPECT_GE(layout.factor_index(0, 2, 1), 0);
}

TEST(CausalGraph, RestrictToOrderAllowsOnlyEarlierCauses) {
  causal::estimation::ModelSpec spec;
  spec.channels = 4;
  const causal::estimation::ModelSpec r = restrict_to_order(spec, {3, 1, 0, 2});
  for (int k = 0; k < 4; ++k) EXPECT_FALSE(r.instantaneous_allowed[k][k]);
  EXPECT_TRUE(r.instantaneous_allowed[1][3]);
  EXPECT_FALSE(r.instantaneous_allowed[3][1]);
  EXPECT_TRUE(r.instantaneous_allowed[2][0]);
  EXPECT_FALSE(r.instantaneous_allowed[0][2]);
  EXPECT_TRUE(CausalGraph::from_mask(r.instantaneous_allowed).is_acyclic());
  EXPECT_EQ(CausalGraph::from_mask(r.instantaneous_allowed).edge_count(), 6);
  // An existing mask is intersected.
  spec.instantaneous_allowed.assign(4, std::vector<bool>(4, true));
  spec.instantaneous_allowed[1][3] = false;
  EXPECT_FALSE(restrict_to_order(spec, {3, 1, 0, 2}).instantaneous_allowed[1][3]);
  EXPECT_THROW(restrict_to_order(spec, {0, 1, 1, 2}), std::invalid_argument);
  EXPECT_THROW(restrict_to_order(spec, {0, 1, 2}), std::invalid_argument);
}

TEST(CausalGraph, CompleteFromOrderMatchesRestrictToOrder) {
  const std::vector<int> order{2, 0, 3, 1};
  causal::estimation::ModelSpec spec;
  spec.channels = 4;
  EXPECT_EQ(CausalGraph::complete_from_order(order).instantaneous_mask(), restrict_to_order(spec, order).instantaneous_allowed);
  EXPECT_EQ(CausalGraph::complete_from_order(order).topological_order(), order);
}

TEST(CausalGraph, ParsesNamesAndIndices) {
  const std::vector<std::string> names{"bearing 1", "bearing 2", "bearing 3"};
  const CausalGraph g = parse_causal_graph("bearing 1 -> bearing 3; 2->3", 3, names);
  EXPECT_TRUE(g.has_edge(0, 2));
  EXPECT_TRUE(g.has_edge(1, 2));
  EXPECT_EQ(g.edge_count(), 2);
  EXPECT_THROW(parse_causal_graph("1 > 2", 3, names), std::invalid_argument);
  EXPECT_THROW(parse_causal_graph("1 -> 4", 3, names), std::invalid_argument);
  EXPECT_THROW(parse_causal_graph("bearing 9 -> 1", 3, names), std::invalid_argument);
  EXPECT_EQ(parse_causal_graph("", 3).edge_count(), 0);
}

}  // namespace
