// Plain-language reasons for alarm events: which channel, what moved from what to what, since when, why
// it is significant (statistic vs threshold and its false-alarm design) and the root cause.
#include <cmath>
#include <iomanip>
#include <sstream>

#include "engine_internal.hpp"

namespace causal::alarms {

namespace {

std::string at(std::uint64_t index, std::int64_t time_ns) {
  return "observation " + std::to_string(index) + " (" + format_utc_seconds(time_ns) + ")";
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

}  // namespace

std::string AlarmEngine::Impl::reason(int c, int kind, AlarmState state, int root, const Observation& obs) const {
  const auto& cs = ch[static_cast<std::size_t>(c)];
  const auto& slot = cs.slots[static_cast<std::size_t>(kind)];
  const std::string& name = names[static_cast<std::size_t>(c)];
  std::ostringstream os;

  if (state == AlarmState::Cleared) {
    os << name << ": " << detail::kind_name(kind) << " alarm cleared at " << at(obs.index, obs.time_ns)
       << ": statistic " << fixed(slot.score, 2) << " stayed below the clear level " << fixed(p.clear_fraction * slot.threshold, 2)
       << " for " << p.clear_persistence << " consecutive observations (raised " << format_utc_seconds(slot.raised_time_ns)
       << ").";
    return os.str();
  }
  if (state == AlarmState::Escalated) os << "Escalated to " << to_string(slot.severity) << ". ";

  switch (kind) {
    case detail::kFeature: {
      const double level = cs.feature.level.median();
      const double now_z = cs.feature.last_z;
      if (p.feature_log_transform) {
        const double ratio_now = std::exp(cs.feature.last_value - cs.feature.stats.location);
        const double ratio_level = std::exp(level * cs.feature.stats.scale);
        os << name << ": condition level " << general(std::exp(cs.feature.last_value)) << " is "
           << signed_fixed(100.0 * (ratio_now - 1.0), 1) << " % (" << signed_fixed(20.0 * std::log10(ratio_now), 1)
           << " dB, " << signed_fixed(now_z, 1) << " baseline sigma) above its healthy baseline median "
           << general(std::exp(cs.feature.stats.location)) << " (median of the last " << p.level_window << ": "
           << signed_fixed(100.0 * (ratio_level - 1.0), 1) << " %)";
      } else {
        os << name << ": condition level " << general(cs.feature.last_value) << " is " << signed_fixed(now_z, 1)
           << " baseline sigma above its healthy baseline median " << general(cs.feature.stats.location)
           << " (median of the last " << p.level_window << ": " << signed_fixed(level, 1) << " sigma)";
      }
      os << "; CUSUM " << fixed(slot.score, 2) << " >= " << fixed(slot.threshold, 2) << " (designed for 1 false alarm per "
         << general(p.target_arl0) << " observations); the rise began at " << at(slot.onset_index, slot.onset_time_ns) << ".";
      break;
    }
    case detail::kInnovation:
      os << name << ": the part of its signal that the other channels do not explain is now "
         << signed_fixed(cs.innovation.last_z, 1) << " baseline sigma (median of the last " << p.level_window << ": "
         << signed_fixed(cs.innovation.level.median(), 1) << "); CUSUM " << fixed(slot.score, 2) << " >= "
         << fixed(slot.threshold, 2) << " (1 false alarm per " << general(p.target_arl0)
         << " observations): its own behaviour changed, starting at " << at(slot.onset_index, slot.onset_time_ns) << ".";
      break;
    case detail::kNis:
      os << name << ": the causal model no longer explains this channel: mean normalised innovation squared"
         << (p.nis_two_sided ? "" : " (upward departures)") << " over the last " << p.nis_window << " observations is "
         << fixed(slot.score, 2) << " (baseline " << (p.nis_two_sided ? "1" : "0.5") << ", threshold " << fixed(slot.threshold, 2)
         << " for a false-alarm probability of " << general(p.nis_false_alarm_prob) << " per observation), raised at "
         << at(obs.index, obs.time_ns) << ".";
      break;
    default:
      os << name << ": the causal factors of its equation left their baseline: max |z| " << fixed(slot.score, 2) << " >= "
         << fixed(slot.threshold, 2) << " (Bonferroni, " << general(p.factor_false_alarm_prob) << " per observation) for "
         << p.factor_persistence << "+ observations since " << at(slot.onset_index, slot.onset_time_ns) << ".";
      break;
  }

  if (state == AlarmState::Escalated) os << " First raised " << format_utc_seconds(slot.raised_time_ns) << ".";
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
