// How outcomes are packed into 4-wide lane groups (see kernels.hpp): outcomes with the same number of
// factors d share a group (up to 4 per group, in outcome order); unused lanes are padding. Outcomes without
// factors (fully masked) are not in any group: their innovation is y_k itself with variance r_k.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "causal/estimation/svar_layout.hpp"
#include "kernels.hpp"

namespace causal::estimation::detail {

struct LaneGroup {
  int d = 0;
  int count = 0;                                   // real lanes (1..4); lanes >= count are padding
  std::array<int, kLanes> outcome{{-1, -1, -1, -1}};
  std::size_t x_off = 0;  // offset in doubles of the group's d-vectors of V4 (x, h, u): d * 4 doubles
  std::size_t p_off = 0;  // offset in doubles of the group's d x d matrix of V4: d * d * 4 doubles
};

struct LanePlan {
  std::vector<LaneGroup> groups;
  std::vector<int> empty;     // outcomes with no factors
  std::vector<int> group_of;  // per outcome, -1 if empty
  std::vector<int> lane_of;   // per outcome, -1 if empty
  std::size_t x_size = 0;     // doubles in all groups' vectors
  std::size_t p_size = 0;     // doubles in all groups' matrices
  int max_d = 0;
};

// Groups of equal dimension over all outcomes of the layout.
LanePlan make_lane_plan(const SvarLayout& layout);

// One group whose lanes all hold outcome k (used to evaluate up to 4 noise candidates in one pass).
LanePlan make_replicated_plan(const SvarLayout& layout, int k);

}  // namespace causal::estimation::detail
