#include "causal/analysis/causal_graph.hpp"

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <stdexcept>

namespace causal::analysis {
namespace {

void check_index(int index, int channels, const char* what) {
  if (index < 0 || index >= channels) {
    throw std::invalid_argument(std::string("causal graph: ") + what + " channel " + std::to_string(index) +
                                " is outside 0.." + std::to_string(channels - 1));
  }
}

std::string trim(const std::string& s) {
  std::size_t b = 0;
  std::size_t e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b])) != 0) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1])) != 0) --e;
  return s.substr(b, e - b);
}

// Channel from a name (exact match preferred) or a 1-based index.
int resolve_channel(const std::string& token, int channels, const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == token) return static_cast<int>(i);
  }
  const bool numeric = !token.empty() && std::all_of(token.begin(), token.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  });
  if (numeric && token.size() < 9) {
    const int one_based = std::stoi(token);
    if (one_based >= 1 && one_based <= channels) return one_based - 1;
  }
  throw std::invalid_argument("causal graph: '" + token + "' is neither a channel name nor a 1-based index 1.." +
                              std::to_string(channels));
}

}  // namespace

void check_permutation(const std::vector<int>& order, int channels) {
  if (static_cast<int>(order.size()) != channels) {
    throw std::invalid_argument("causal order has " + std::to_string(order.size()) + " entries, expected " +
                                std::to_string(channels));
  }
  std::vector<bool> seen(static_cast<std::size_t>(channels), false);
  for (int c : order) {
    check_index(c, channels, "order");
    if (seen[c]) throw std::invalid_argument("causal order lists channel " + std::to_string(c) + " twice");
    seen[c] = true;
  }
}

CausalGraph::CausalGraph(int channels) : channels_(channels) {
  if (channels < 1) throw std::invalid_argument("causal graph needs at least one channel");
  adjacent_.assign(static_cast<std::size_t>(channels), std::vector<bool>(static_cast<std::size_t>(channels), false));
}

CausalGraph CausalGraph::complete_from_order(const std::vector<int>& order) {
  const int g = static_cast<int>(order.size());
  CausalGraph graph(g);
  check_permutation(order, g);
  for (int a = 0; a < g; ++a) {
    for (int b = a + 1; b < g; ++b) graph.add_edge(order[a], order[b]);
  }
  return graph;
}

CausalGraph CausalGraph::from_mask(const std::vector<std::vector<bool>>& instantaneous_allowed) {
  const int g = static_cast<int>(instantaneous_allowed.size());
  CausalGraph graph(g);
  for (int k = 0; k < g; ++k) {
    if (static_cast<int>(instantaneous_allowed[k].size()) != g) {
      throw std::invalid_argument("instantaneous mask is not square");
    }
    for (int j = 0; j < g; ++j) {
      if (j != k && instantaneous_allowed[k][j]) graph.add_edge(j, k);
    }
  }
  return graph;
}

void CausalGraph::add_edge(int from, int to) {
  check_index(from, channels_, "source");
  check_index(to, channels_, "target");
  if (from == to) throw std::invalid_argument("causal graph: self-loop on channel " + std::to_string(from));
  adjacent_[from][to] = true;
}

void CausalGraph::remove_edge(int from, int to) {
  check_index(from, channels_, "source");
  check_index(to, channels_, "target");
  adjacent_[from][to] = false;
}

bool CausalGraph::has_edge(int from, int to) const {
  check_index(from, channels_, "source");
  check_index(to, channels_, "target");
  return adjacent_[from][to];
}

int CausalGraph::edge_count() const {
  int n = 0;
  for (const auto& row : adjacent_) n += static_cast<int>(std::count(row.begin(), row.end(), true));
  return n;
}

std::vector<int> CausalGraph::find_cycle() const {
  // Iterative-enough DFS with colours (G is small: recursion depth <= G).
  enum Colour { white, grey, black };
  std::vector<Colour> colour(static_cast<std::size_t>(channels_), white);
  std::vector<int> stack;
  std::vector<int> cycle;
  auto visit = [&](auto&& self, int v) -> bool {
    colour[v] = grey;
    stack.push_back(v);
    for (int w = 0; w < channels_; ++w) {
      if (!adjacent_[v][w]) continue;
      if (colour[w] == grey) {
        auto it = std::find(stack.begin(), stack.end(), w);
        cycle.assign(it, stack.end());
        return true;
      }
      if (colour[w] == white && self(self, w)) return true;
    }
    stack.pop_back();
    colour[v] = black;
    return false;
  };
  for (int v = 0; v < channels_; ++v) {
    if (colour[v] == white && visit(visit, v)) return cycle;
  }
  return {};
}

std::vector<int> CausalGraph::topological_order() const {
  const std::vector<int> cycle = find_cycle();
  if (!cycle.empty()) {
    throw std::invalid_argument("instantaneous causal graph has a cycle: " + describe_cycle(cycle) +
                                " (1-based channels); instantaneous links must be acyclic");
  }
  // Kahn's algorithm, smallest index first among the ready channels (deterministic).
  std::vector<int> indegree(static_cast<std::size_t>(channels_), 0);
  for (int v = 0; v < channels_; ++v)
    for (int w = 0; w < channels_; ++w)
      if (adjacent_[v][w]) ++indegree[w];
  std::vector<int> order;
  std::vector<bool> done(static_cast<std::size_t>(channels_), false);
  while (static_cast<int>(order.size()) < channels_) {
    int next = -1;
    for (int v = 0; v < channels_ && next < 0; ++v)
      if (!done[v] && indegree[v] == 0) next = v;
    done[next] = true;  // exists: the graph is acyclic
    order.push_back(next);
    for (int w = 0; w < channels_; ++w)
      if (adjacent_[next][w]) --indegree[w];
  }
  return order;
}

std::vector<std::vector<bool>> CausalGraph::instantaneous_mask() const {
  std::vector<std::vector<bool>> mask(static_cast<std::size_t>(channels_),
                                      std::vector<bool>(static_cast<std::size_t>(channels_), false));
  for (int k = 0; k < channels_; ++k)
    for (int j = 0; j < channels_; ++j) mask[k][j] = adjacent_[j][k];
  return mask;
}

estimation::ModelSpec CausalGraph::apply_to(estimation::ModelSpec spec) const {
  if (spec.channels != channels_) {
    throw std::invalid_argument("causal graph has " + std::to_string(channels_) + " channels but the model spec " +
                                std::to_string(spec.channels));
  }
  (void)topological_order();  // throws with the cycle named
  spec.instantaneous_allowed = instantaneous_mask();
  return spec;
}

std::string describe_cycle(const std::vector<int>& cycle, const std::vector<std::string>& names) {
  if (cycle.empty()) return "";
  auto name = [&](int c) {
    if (c >= 0 && c < static_cast<int>(names.size())) return names[c];
    return std::to_string(c + 1);
  };
  std::string text;
  for (int c : cycle) text += name(c) + " -> ";
  return text + name(cycle.front());
}

CausalGraph parse_causal_graph(const std::string& text, int channels, const std::vector<std::string>& names) {
  CausalGraph graph(channels);
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find_first_of(",;", start);
    if (end == std::string::npos) end = text.size();
    const std::string edge = trim(text.substr(start, end - start));
    start = end + 1;
    if (edge.empty()) continue;
    const std::size_t arrow = edge.find("->");
    if (arrow == std::string::npos) {
      throw std::invalid_argument("causal graph: edge '" + edge + "' has no '->'");
    }
    const int from = resolve_channel(trim(edge.substr(0, arrow)), channels, names);
    const int to = resolve_channel(trim(edge.substr(arrow + 2)), channels, names);
    graph.add_edge(from, to);
  }
  return graph;
}

estimation::ModelSpec restrict_to_order(estimation::ModelSpec spec, const std::vector<int>& order) {
  check_permutation(order, spec.channels);
  const std::size_t g = static_cast<std::size_t>(spec.channels);
  std::vector<int> position(g);
  for (std::size_t p = 0; p < g; ++p) position[order[p]] = static_cast<int>(p);
  const bool had_mask = !spec.instantaneous_allowed.empty();
  if (had_mask && spec.instantaneous_allowed.size() != g) {
    throw std::invalid_argument("model spec instantaneous_allowed is not channels x channels");
  }
  std::vector<std::vector<bool>> mask(g, std::vector<bool>(g, false));
  for (std::size_t k = 0; k < g; ++k) {
    if (had_mask && spec.instantaneous_allowed[k].size() != g) {
      throw std::invalid_argument("model spec instantaneous_allowed is not channels x channels");
    }
    for (std::size_t j = 0; j < g; ++j) {
      mask[k][j] = j != k && position[j] < position[k] && (!had_mask || spec.instantaneous_allowed[k][j]);
    }
  }
  spec.instantaneous_allowed = std::move(mask);
  return spec;
}

}  // namespace causal::analysis
