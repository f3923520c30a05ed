#include "causal/intervention/lever_trust.hpp"

#include <cmath>
#include <stdexcept>

namespace causal::intervention {

LeverTrust::LeverTrust(LeverTrustParams params) : params_(params) {
  if (!(params_.prior_checks > 0.0) || !(params_.prior_hits >= 0.0) || params_.prior_hits > params_.prior_checks ||
      !(params_.min_trust >= 0.0 && params_.min_trust <= 1.0)) {
    throw std::invalid_argument("lever trust: need 0 <= prior_hits <= prior_checks, prior_checks > 0, min_trust in [0, 1]");
  }
}

void LeverTrust::record(const std::string& group, int lever, int target, bool inside, bool improved) {
  auto& r = records_[Key{group, lever, target}];
  ++r.checks;
  r.hits += inside ? 1 : 0;
  r.improved += improved ? 1 : 0;
}

LeverRecord LeverTrust::record_of(const std::string& group, int lever, int target) const {
  const auto it = records_.find(Key{group, lever, target});
  return it == records_.end() ? LeverRecord{} : it->second;
}

double LeverTrust::trust(const std::string& group, int lever, int target) const {
  const LeverRecord r = record_of(group, lever, target);
  return (static_cast<double>(r.hits) + params_.prior_hits) / (static_cast<double>(r.checks) + params_.prior_checks);
}

}  // namespace causal::intervention
