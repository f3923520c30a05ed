// Configured instantaneous causal graph -> ModelSpec mask for the estimator.
//
// Why a graph at all: the estimator fits one regression per outcome k on the other channels' current
// values. If both x_kj and x_jk are free, the G regressions are not jointly one structural model: the
// system y = A0 y + ... + e can be non-identified and (I - A0) may even be singular. Restricting the
// instantaneous links to a directed ACYCLIC graph (a causal order) makes A0 permutable to strictly
// triangular form, so (I - A0) is always invertible (unit determinant) and every outcome regression is
// a structural equation. Lagged links are not restricted here: they cannot form instantaneous loops.
#pragma once

#include <causal/estimation/svar_layout.hpp>

#include <string>
#include <vector>

namespace causal::analysis {

// Directed graph over G channels (0-based). Edge from -> to means y_from[n] may enter the equation of
// y_to[n] (factor x_{to,from}).
class CausalGraph {
 public:
  explicit CausalGraph(int channels);  // no edges; throws std::invalid_argument if channels < 1

  // Every edge consistent with the order: order[a] -> order[b] for all a < b. order must be a permutation.
  static CausalGraph complete_from_order(const std::vector<int>& order);
  // From a ModelSpec-style mask [k][j] (true = j may cause k instantaneously); the diagonal is ignored.
  static CausalGraph from_mask(const std::vector<std::vector<bool>>& instantaneous_allowed);

  int channels() const { return channels_; }
  void add_edge(int from, int to);  // throws std::invalid_argument on a self-loop or bad index
  void remove_edge(int from, int to);
  bool has_edge(int from, int to) const;
  int edge_count() const;

  // One directed cycle as the list of channels c0 -> c1 -> ... -> c_{m-1} (-> c0); empty when acyclic.
  std::vector<int> find_cycle() const;
  bool is_acyclic() const { return find_cycle().empty(); }
  // A topological order (causes first; ties by index). Throws std::invalid_argument naming the cycle.
  std::vector<int> topological_order() const;

  // [k][j] = has_edge(j, k); the layout of ModelSpec::instantaneous_allowed.
  std::vector<std::vector<bool>> instantaneous_mask() const;
  // spec with instantaneous_allowed replaced by this graph's mask. Throws std::invalid_argument when the
  // graph has a cycle (message names it) or spec.channels != channels().
  estimation::ModelSpec apply_to(estimation::ModelSpec spec) const;

 private:
  int channels_;
  std::vector<std::vector<bool>> adjacent_;  // [from][to]
};

// "c1 -> c2 -> c3 -> c1" using names (1-based numbers when names is empty).
std::string describe_cycle(const std::vector<int>& cycle, const std::vector<std::string>& names = {});

// Parses "1->2, 2->4" or "bearing 1 -> bearing 3; bearing 2 -> bearing 3": edges separated by ',' or ';',
// each side a channel name from `names` or a 1-based index. Throws std::invalid_argument with the
// offending token. Cycles are NOT rejected here (call find_cycle / apply_to).
[[nodiscard]] CausalGraph parse_causal_graph(const std::string& text, int channels, const std::vector<std::string>& names = {});

// Restricts spec to a causal order: j may cause k instantaneously only if j precedes k. An existing
// spec.instantaneous_allowed mask is intersected (links it forbids stay forbidden).
estimation::ModelSpec restrict_to_order(estimation::ModelSpec spec, const std::vector<int>& order);

// Throws std::invalid_argument unless order is a permutation of 0..channels-1.
void check_permutation(const std::vector<int>& order, int channels);

}  // namespace causal::analysis
