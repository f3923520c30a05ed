// Lever trust per asset group: how often a lever's checked outcomes fell inside the interval the twin predicted.
// A lever whose outcomes miss loses its claim. Trust is the posterior mean of a hit rate under a prior worth
// `prior_hits` hits in `prior_checks` checks,
//     trust = (hits + prior_hits) / (checks + prior_checks),                                    (T1)
// and the lever may be claimed while trust >= min_trust. With the defaults (2 in 3, 0.5): one miss in the
// first check keeps the claim (2/4: one miss in ten is what a 90 % interval promises), two misses in a row
// withdraw it (2/5). Std only.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <tuple>

namespace causal::intervention {

struct LeverTrustParams {
  double prior_hits = 2.0;
  double prior_checks = 3.0;
  double min_trust = 0.5;
};

struct LeverRecord {
  std::uint64_t checks = 0, hits = 0, improved = 0;
};

class LeverTrust {
 public:
  explicit LeverTrust(LeverTrustParams params = {});  // throws std::invalid_argument for inconsistent params
  // One checked outcome of lever `lever` on `target` (0-based channels) in `group`.
  void record(const std::string& group, int lever, int target, bool inside, bool improved);
  double trust(const std::string& group, int lever, int target) const;  // (T1); the prior alone when never checked
  bool claimed(const std::string& group, int lever, int target) const { return trust(group, lever, target) >= params_.min_trust; }
  LeverRecord record_of(const std::string& group, int lever, int target) const;

 private:
  using Key = std::tuple<std::string, int, int>;
  LeverTrustParams params_;
  std::map<Key, LeverRecord> records_;
};

}  // namespace causal::intervention
