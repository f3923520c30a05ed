// Root cause, severity and factor selection of AlarmEngine (the "explain" half of the engine's logic).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

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
  return detail::detector_table()[static_cast<std::size_t>(kind)].level_severity(*this, c);
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

namespace causal::alarms {

std::vector<double> AlarmEngine::Impl::departed_evidence() const {
  std::vector<double> e(ch.size(), detail::kNaN);
  for (std::size_t j = 0; j < ch.size(); ++j)
    if (ch[j].feature.cusum.in_excursion() || ch[j].any_active()) e[j] = ch[j].own_evidence();
  return e;
}

int AlarmEngine::Impl::attribution_rival(int root, const std::vector<double>& evidence) const {
  if (root < 0 || static_cast<std::size_t>(root) >= evidence.size()) return -1;
  // The rivals are the channels that could have been named instead: by root_cause's own rule (the earliest
  // onset wins) those whose trouble began no later than the root's, within onset_tolerance. A channel that
  // departed later (the failure spreading to its neighbours, another bearing's wear days later) changed too,
  // but did not start this; against the maximum over every departed channel the confidence fell towards 0
  // with the group's width (20 channels: 0.00 on most events of IMS test 2's copies).
  auto onset = [&](std::size_t j) {
    const auto& o = episode.own[j];
    const auto& d = episode.departure[j];
    return std::min(o.set ? o.index : ~std::uint64_t{0}, d.set ? d.index : ~std::uint64_t{0});
  };
  const std::uint64_t root_onset = onset(static_cast<std::size_t>(root));
  const bool timed = root_onset != ~std::uint64_t{0};
  int best = -1;
  for (std::size_t j = 0; j < evidence.size(); ++j) {
    if (static_cast<int>(j) == root || !std::isfinite(evidence[j])) continue;
    if (timed && onset(j) > root_onset + static_cast<std::uint64_t>(p.onset_tolerance)) continue;
    if (best < 0 || evidence[j] > evidence[static_cast<std::size_t>(best)]) best = static_cast<int>(j);
  }
  return best;
}

double AlarmEngine::Impl::attribution_confidence(int root, const std::vector<double>& evidence) const {
  if (root < 0 || static_cast<std::size_t>(root) >= evidence.size()) return 0.0;
  const double er = std::isfinite(evidence[static_cast<std::size_t>(root)]) ? evidence[static_cast<std::size_t>(root)] : 0.0;
  const int rival = attribution_rival(root, evidence);
  if (rival < 0) return 1.0;  // no other channel departed first or with it: nothing else to blame
  // P(E_root > E_next) for two unit-variance statistics: Phi(d / sqrt(2)) = erfc(-d / 2) / 2.
  return 0.5 * std::erfc(-(er - evidence[static_cast<std::size_t>(rival)]) / 2.0);
}

std::string AlarmEngine::Impl::reevaluate_root(int c, detail::AlarmSlot& slot, const std::vector<double>& evidence) {
  (void)c;
  const int r = slot.root;
  const double er = r >= 0 && std::isfinite(evidence[static_cast<std::size_t>(r)]) ? evidence[static_cast<std::size_t>(r)] : 0.0;
  int best = -1;
  double eb = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < evidence.size(); ++j)
    if (static_cast<int>(j) != r && std::isfinite(evidence[j]) && evidence[j] > eb) {
      eb = evidence[j];
      best = static_cast<int>(j);
    }
  // A challenger takes over only when the named root's own trouble is over (none of its alarms is active:
  // it is not what keeps degrading) and its own-change evidence is gone, while the challenger shows own
  // change by the margin, for root_cause_persistence consecutive observations.
  const bool root_over = r < 0 || !ch[static_cast<std::size_t>(r)].any_active();
  const bool challenge = best >= 0 && root_over && er < p.own_evidence_z && eb >= p.own_evidence_z &&
                         eb - er >= p.root_cause_margin_z;
  if (!challenge) {
    slot.challenger = -1;
    slot.challenger_run = 0;
    return {};
  }
  if (best != slot.challenger) {
    slot.challenger = best;
    slot.challenger_run = 0;
  }
  if (++slot.challenger_run < p.root_cause_persistence) return {};
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << "Root cause re-evaluated: " << (r >= 0 ? names[static_cast<std::size_t>(r)] : "unknown")
     << " -> " << names[static_cast<std::size_t>(best)] << ": " << names[static_cast<std::size_t>(best)]
     << "'s own, unexplained change has evidence z = " << eb << " for " << slot.challenger_run
     << " observations while " << (r >= 0 ? names[static_cast<std::size_t>(r)] : "the named root") << "'s is " << er
     << " (margin " << p.root_cause_margin_z << ").";
  slot.root = best;
  slot.challenger = -1;
  slot.challenger_run = 0;
  return os.str();
}

}  // namespace causal::alarms
