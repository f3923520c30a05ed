#include "causal/alarms/observation_builder.hpp"

#include <limits>

namespace causal::alarms {

Observation observation_from_outcomes(std::uint64_t index, std::int64_t time_ns,
                                      const std::vector<OutcomeReport>& outcomes, bool sample_level) {
  const auto g = static_cast<Eigen::Index>(outcomes.size());
  Observation o;
  o.index = index;
  o.time_ns = time_ns;
  Eigen::Index f = 0;
  for (const auto& r : outcomes) f += r.factors.size();
  o.factors.resize(f);
  o.factor_std.resize(f);
  Eigen::Index at = 0;
  for (const auto& r : outcomes) {
    o.factors.segment(at, r.factors.size()) = r.factors;
    if (r.factor_std.size() == r.factors.size())
      o.factor_std.segment(at, r.factors.size()) = r.factor_std;
    else
      o.factor_std.segment(at, r.factors.size()).setZero();
    at += r.factors.size();
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  o.innovations.resize(g);
  o.innovation_variances.resize(g);
  if (sample_level) o.mean_nis.resize(g);
  for (Eigen::Index k = 0; k < g; ++k) {
    const auto& r = outcomes[static_cast<std::size_t>(k)];
    const bool fresh = r.innovation_count > 0;
    o.innovations[k] = fresh ? r.last_innovation : nan;
    o.innovation_variances[k] = fresh ? r.last_innovation_variance : nan;
    if (sample_level) o.mean_nis[k] = fresh ? r.nis_mean : nan;
  }
  return o;
}

}  // namespace causal::alarms
