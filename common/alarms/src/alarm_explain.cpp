// Plain-language reasons for alarm events: which channel, what moved from what to what, since when, why
// it is significant (statistic vs threshold and its false-alarm design) and the root cause.
#include <cmath>
#include <iomanip>
#include <sstream>

#include "engine_internal.hpp"
#include "causal/io/time_format.hpp"

namespace causal::alarms {

namespace detail {

std::string at(std::uint64_t index, std::int64_t time_ns) {
  return "observation " + std::to_string(index) + " (" + io::format_utc_seconds(time_ns) + ")";
}

std::string signed_fixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << std::showpos << v;
  return os.str();
}

std::string fixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}

std::string general(double v) {
  std::ostringstream os;
  os << std::setprecision(4) << v;
  return os.str();
}

}  // namespace detail

using detail::at;
using detail::fixed;
using detail::general;
using detail::signed_fixed;

std::string AlarmEngine::Impl::reason(int c, int kind, AlarmState state, int root, const Observation& obs) const {
  const auto& cs = ch[static_cast<std::size_t>(c)];
  const auto& slot = cs.slots[static_cast<std::size_t>(kind)];
  const std::string& name = names[static_cast<std::size_t>(c)];
  std::ostringstream os;

  if (state == AlarmState::Cleared) {
    os << name << ": " << detail::kind_name(kind) << " alarm cleared at " << at(obs.index, obs.time_ns)
       << ": statistic " << fixed(slot.score, 2) << " stayed below the clear level " << fixed(p.clear_fraction * slot.threshold, 2)
       << " for " << p.clear_persistence << " consecutive observations (raised " << io::format_utc_seconds(slot.raised_time_ns)
       << ").";
    return os.str();
  }
  if (state == AlarmState::Escalated) os << "Escalated to " << to_string(slot.severity) << ". ";

  os << detail::detector_table()[static_cast<std::size_t>(kind)].describe(*this, c, slot, obs);

  if (state == AlarmState::Escalated) os << " First raised " << io::format_utc_seconds(slot.raised_time_ns) << ".";
  os << " Root cause: ";
  if (root < 0) {
    os << "unknown (no channel's own behaviour or level has departed from its baseline).";
  } else {
    const auto& own = episode.own[static_cast<std::size_t>(root)];
    const auto& dep = episode.departure[static_cast<std::size_t>(root)];
    const std::string& rname = names[static_cast<std::size_t>(root)];
    if (root == c)
      os << rname << " itself";
    else
      os << rname;
    if (own.set)
      os << ": its own, unexplained behaviour changed (from " << at(own.index, own.time_ns) << ", "
         << signed_fixed(own.level, 1) << " sigma)";
    else if (dep.set && dep.evidence >= p.own_evidence_z)
      os << ": its rise from " << at(dep.index, dep.time_ns) << " is not explained by the other channels (own-change "
         << "evidence z = " << fixed(dep.evidence, 1) << ")";
    else if (dep.set)
      os << ": its level departed first (from " << at(dep.index, dep.time_ns)
         << ") and no channel's own behaviour changed before it";
    if (root != c) os << "; " << name << " follows it through the causal links";
    os << ".";
    // A low confidence says who else could be the root (alarm_attribution.cpp): a channel whose trouble began
    // no later, with more own-change evidence now (e.g. another sensor of the same bearing).
    const auto evidence = departed_evidence();
    const int rival = slot.root_confidence < 0.5 ? attribution_rival(root, evidence) : -1;
    if (rival >= 0)
      os << " Attribution confidence " << fixed(slot.root_confidence, 2) << ": "
         << names[static_cast<std::size_t>(rival)] << ", whose trouble began no later, shows more own-change "
         << "evidence now (z = " << fixed(evidence[static_cast<std::size_t>(rival)], 1) << " against "
         << fixed(std::isfinite(evidence[static_cast<std::size_t>(root)]) ? evidence[static_cast<std::size_t>(root)] : 0.0, 1)
         << "): the root may be either.";
  }

  const auto factors = explain_factors(c, root);
  if (!factors.empty()) {
    os << " Factors that moved:";
    for (std::size_t n = 0; n < factors.size(); ++n) {
      const auto& f = fac[static_cast<std::size_t>(factors[n])];
      os << (n ? ", " : " ") << factor_names[static_cast<std::size_t>(factors[n])] << " " << fixed(f.stats.location, 3)
         << " -> " << fixed(f.last_value, 3) << " (" << signed_fixed(f.last_z, 1) << " sigma)";
    }
    os << ".";
  }
  return os.str();
}

}  // namespace causal::alarms
