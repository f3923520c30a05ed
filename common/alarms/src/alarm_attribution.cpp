// Root cause, severity and factor selection of AlarmEngine (the "explain" half of the engine's logic).
#include <algorithm>
#include <cmath>

#include "engine_internal.hpp"

namespace causal::alarms {

int AlarmEngine::Impl::root_cause(int c, std::uint64_t event_onset) const {
  // This channel's trouble began at the earliest onset among its currently active alarms and the alarm
  // being reported (a cleared, earlier alarm of the channel does not count: it was a separate matter).
  std::uint64_t since = event_onset;
  for (const auto& s : ch[static_cast<std::size_t>(c)].slots)
    if (s.latch.active()) since = std::min(since, s.onset_index);
  const std::uint64_t limit = since + static_cast<std::uint64_t>(p.onset_tolerance);
  // Among the channels whose onset is no later than this channel's (within the tolerance), the earliest
  // onset wins; onsets within onset_tolerance of that earliest one count as simultaneous (CUSUM change
  // points are uncertain by an observation or two). Among simultaneous departures the one with the
  // strongest own-change evidence wins (its rise is the least explained by the other channels: a root,
  // not a follower), then the larger level.
  auto earliest = [&](const std::vector<detail::Onset>& onsets) {
    bool any = false;
    std::uint64_t first_onset = 0;
    for (const auto& o : onsets)
      if (o.set && o.index <= limit && (!any || o.index < first_onset)) {
        any = true;
        first_onset = o.index;
      }
    int best = -1;
    if (!any) return best;
    const std::uint64_t tie = first_onset + static_cast<std::uint64_t>(p.onset_tolerance);
    for (int j = 0; j < channels(); ++j) {
      const auto& o = onsets[static_cast<std::size_t>(j)];
      if (!o.set || o.index > limit || o.index > tie) continue;
      if (best < 0) {
        best = j;
        continue;
      }
      const auto& b = onsets[static_cast<std::size_t>(best)];
      if (o.evidence > b.evidence || (o.evidence == b.evidence && o.level > b.level)) best = j;
    }
    return best;
  };
  // Did this channel's trouble begin with an own change of its own (an own-change alarm, or a departure
  // whose innovations show significant unexplained rise)? Then it is an independent root unless it
  // belongs to the group's first (simultaneous) root change.
  const auto& own_c = episode.own[static_cast<std::size_t>(c)];
  const auto& dep_c = episode.departure[static_cast<std::size_t>(c)];
  const bool own_start = (own_c.set && own_c.index <= limit) ||
                         (dep_c.set && dep_c.index <= limit && dep_c.evidence >= p.own_evidence_z);
  const std::uint64_t own_start_index = std::min(own_c.set ? own_c.index : ~std::uint64_t{0},
                                                 dep_c.set && dep_c.evidence >= p.own_evidence_z ? dep_c.index : ~std::uint64_t{0});
  const auto tol = static_cast<std::uint64_t>(p.onset_tolerance);
  const int own = earliest(episode.own);
  if (own >= 0) {
    if (own != c && own_start && own_start_index > episode.own[static_cast<std::size_t>(own)].index + tol) return c;
    return own;
  }
  const int dep = earliest(episode.departure);
  if (dep >= 0 && dep != c && own_start && own_start_index > episode.departure[static_cast<std::size_t>(dep)].index + tol)
    return c;
  return dep;
}

Severity AlarmEngine::Impl::severity_for(int c, int kind) const {
  const auto& cs = ch[static_cast<std::size_t>(c)];
  auto by_sigma = [&](double level) {
    if (!std::isfinite(level)) return Severity::Advisory;
    if (level >= p.critical_sigma) return Severity::Critical;
    if (level >= p.warning_sigma) return Severity::Warning;
    return Severity::Advisory;
  };
  switch (kind) {
    case detail::kFeature: {
      const double level = cs.feature.level.median();
      if (!p.feature_log_transform) return by_sigma(level);
      if (!std::isfinite(level)) return Severity::Advisory;
      // Physical ratio of the current level to the baseline median: exp(z * scale) in log units.
      const double ratio = std::exp(level * cs.feature.stats.scale);
      if (ratio >= p.critical_ratio) return Severity::Critical;
      if (ratio >= p.warning_ratio) return Severity::Warning;
      return Severity::Advisory;
    }
    case detail::kInnovation: return by_sigma(cs.innovation.level.median());  // upward departures only
    case detail::kNis: {
      const double level = cs.innovation.level.median();
      return by_sigma(p.nis_two_sided ? std::abs(level) : level);
    }
    default: return by_sigma(cs.factor_stat);
  }
}

std::vector<int> AlarmEngine::Impl::explain_factors(int c, int root) const {
  const auto& cs = ch[static_cast<std::size_t>(c)];
  std::vector<int> cand;
  for (int i : cs.factors)
    if (fac[static_cast<std::size_t>(i)].monitored && std::isfinite(fac[static_cast<std::size_t>(i)].last_z)) cand.push_back(i);
  auto absz = [&](int i) { return std::abs(fac[static_cast<std::size_t>(i)].last_z); };
  // Links from the root cause into this channel's equation come first (they carry the change), then the
  // factors that moved most.
  std::stable_sort(cand.begin(), cand.end(), [&](int a, int b) {
    const bool la = root >= 0 && root != c && fac[static_cast<std::size_t>(a)].ref.regressor == root;
    const bool lb = root >= 0 && root != c && fac[static_cast<std::size_t>(b)].ref.regressor == root;
    if (la != lb) return la;
    return absz(a) > absz(b);
  });
  if (cand.size() > static_cast<std::size_t>(p.explain_top_factors)) cand.resize(static_cast<std::size_t>(p.explain_top_factors));
  return cand;
}

}  // namespace causal::alarms
