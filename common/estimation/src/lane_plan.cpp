#include "lane_plan.hpp"

#include <algorithm>

namespace causal::estimation::detail {
namespace {

void add_group(LanePlan& plan, int d, const std::vector<int>& members) {
  LaneGroup g;
  g.d = d;
  g.count = static_cast<int>(members.size());
  for (int w = 0; w < g.count; ++w) g.outcome[w] = members[w];
  g.x_off = plan.x_size;
  g.p_off = plan.p_size;
  plan.x_size += static_cast<std::size_t>(d) * kLanes;
  plan.p_size += static_cast<std::size_t>(d) * d * kLanes;
  plan.max_d = std::max(plan.max_d, d);
  plan.groups.push_back(g);
}

}  // namespace

LanePlan make_lane_plan(const SvarLayout& layout) {
  LanePlan plan;
  const int g = layout.channels();
  plan.group_of.assign(g, -1);
  plan.lane_of.assign(g, -1);
  std::vector<bool> placed(g, false);
  for (int k = 0; k < g; ++k) {
    if (placed[k]) continue;
    const int d = layout.factor_count(k);
    if (d == 0) {
      plan.empty.push_back(k);
      placed[k] = true;
      continue;
    }
    std::vector<int> members;
    for (int j = k; j < g && static_cast<int>(members.size()) < kLanes; ++j) {
      if (!placed[j] && layout.factor_count(j) == d) {
        members.push_back(j);
        placed[j] = true;
      }
    }
    for (std::size_t w = 0; w < members.size(); ++w) {
      plan.group_of[members[w]] = static_cast<int>(plan.groups.size());
      plan.lane_of[members[w]] = static_cast<int>(w);
    }
    add_group(plan, d, members);
  }
  return plan;
}

LanePlan make_replicated_plan(const SvarLayout& layout, int k) {
  LanePlan plan;
  plan.group_of.assign(layout.channels(), -1);
  plan.lane_of.assign(layout.channels(), -1);
  plan.group_of[k] = 0;
  plan.lane_of[k] = 0;
  add_group(plan, layout.factor_count(k), std::vector<int>(kLanes, k));
  return plan;
}

}  // namespace causal::estimation::detail
