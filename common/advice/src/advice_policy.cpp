#include "causal/advice/advice_policy.hpp"

#include "causal/io/time_format.hpp"

#include "causal/analysis/effect_units.hpp"

#include <cstdio>

namespace causal::advice {

using analysis::interval_level_factor;

bool order_trusted(const OrderTrust& t, const PolicyParams& p, std::string& why) {
  if (t.source == "configured") return true;
  char buf[200];
  if (t.source == "learned" && std::isfinite(t.confidence) && t.confidence >= p.min_order_confidence) return true;
  if (t.source.empty() || !std::isfinite(t.confidence)) {
    why = "the causal order was not assessed (no learned or configured order): no lever claim";
  } else {
    std::snprintf(buf, sizeof buf, "the learned causal order is %s (stability %.2f, needed %.2f): no lever claim without "
                  "a configured instantaneous_graph", t.source == "untrusted" ? "untrusted" : "not stable enough",
                  t.confidence, p.min_order_confidence);
    why = buf;
  }
  return false;
}

bool is_failing(const AlarmSituation& s, int channel) {
  if (channel == s.target) return true;
  for (const auto& a : s.open_alarms) {
    if (a.category == alarms::category::kDegradation && a.channel == channel &&
        static_cast<int>(a.severity) >= static_cast<int>(s.severity))
      return true;
  }
  return false;
}

std::string hours_text(double hours) {
  if (!std::isfinite(hours)) return "?";
  char buf[48];
  if (hours < 48.0) {
    std::snprintf(buf, sizeof buf, "%.1f h", hours);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f days", hours / 24.0);
  }
  return buf;
}

namespace {

const std::string& name_of(const AlarmSituation& s, int j) { return s.channel_names[static_cast<std::size_t>(j)]; }

// "at steady state" or "within 12 snapshots (2.0 h, by 2004-02-18 12:32:00 UTC)".
std::string when_text(const AdviceItem& c, const AlarmSituation& s) {
  if (c.diag.kind == "steady_state") return "at steady state";
  std::string t = "within " + std::to_string(c.diag.horizon_snapshots) + " snapshots";
  const double h = c.diag.horizon_snapshots * s.snapshot_hours;
  if (std::isfinite(h)) {
    t += " (" + hours_text(h) + ", by " +
         io::format_utc_seconds(s.time_ns + static_cast<std::int64_t>(h * 3600.0 * 1e9)) + ")";
  }
  return t;
}

std::string effect_text(const AdviceItem& c, const PolicyParams& p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%g %%", 100.0 * c.coverage);
  if (interval_level_factor(c.percent_lower, c.percent_upper) > p.max_interval_factor) {
    std::snprintf(buf, sizeof buf, "effect unknown (its %g %% interval spans more than a factor of %g in level)",
                  100.0 * c.coverage, p.max_interval_factor);
    return buf;
  }
  return analysis::percent_text(c.percent) + " [" + analysis::percent_text(c.percent_lower) + ", " +
         analysis::percent_text(c.percent_upper) + "] (" + buf + ")";
}

// Empty when a lever claim on candidate c may be made; else why not.
std::string claim_problem(const AlarmSituation& s, const AdviceItem& c, bool check_failing, bool trusted,
                          const std::string& trust_why, const PolicyParams& p) {
  if (check_failing && is_failing(s, c.intervene)) {
    return name_of(s, c.intervene) + " is failing itself (an open alarm at this severity or worse): not a lever";
  }
  if (c.diag.kind == "refused" || !std::isfinite(c.effect)) return "the model refused the question (" + c.summary + ")";
  if (interval_level_factor(c.percent_lower, c.percent_upper) > p.max_interval_factor) {
    return "reducing " + name_of(s, c.intervene) + ": " + effect_text(c, p);
  }
  if (!c.reliable) {
    return "reducing " + name_of(s, c.intervene) + " gives " + name_of(s, s.target) + " " + effect_text(c, p) +
           ": the interval includes no change";
  }
  if (!trusted) return trust_why;
  if (c.reference == "appeared") {
    // Both rising at once from their own causes looks like a new link to a time-varying model: a lever must
    // have been one while the plant was healthy (docs/advice.md, "A lever must predate the fault").
    // The reference's own number is not quoted: the reference is not checkpointed, so after a restart it is
    // rebuilt from other snapshots and the number would change while the decision does not (fault_plant_day).
    return "the link from " + name_of(s, c.intervene) + " to " + name_of(s, s.target) +
           " was not in the healthy model: it came with the fault, and a common cause of both rises explains it "
           "as well";
  }
  return "";
}

AdviceItem base_item(const AlarmSituation& s, int act_on) {
  AdviceItem a;
  a.target = s.target;
  a.intervene = act_on;
  a.delta = a.immediate = a.steady_state = a.effect = a.lower = a.upper = NAN;
  a.percent = a.percent_lower = a.percent_upper = a.level_change = NAN;
  a.coverage = NAN;
  a.reliable = false;
  return a;
}

Decision act_on_asset(const AlarmSituation& s, int j, const ActionCatalogue& catalogue, const AdviceItem* support,
                      std::string note) {
  Decision d;
  d.kind = "act_on_asset";
  d.act_on = j;
  const char* sev = alarms::to_string(s.severity);
  d.action = "Act on " + name_of(s, j) +
             (j == s.target ? std::string(" (") + sev + " alarm)"
                            : std::string(" (root cause of the ") + sev + " alarm on " + name_of(s, s.target) + ")") +
             ": " + catalogue.actions(s.asset_group, name_of(s, j), s.severity) + ".";
  AdviceItem item = support != nullptr ? *support : base_item(s, j);
  item.intervene = j;
  item.rank = 1;
  d.note = std::move(note);
  item.text = d.action + (d.note.empty() ? "" : " " + d.note);
  item.action = d.action;
  d.items.push_back(std::move(item));
  return d;
}

}  // namespace

Decision decide(const AlarmSituation& s, const std::vector<AdviceItem>& candidates, const std::string& advisor_why,
                const OrderTrust& trust, const ActionCatalogue& catalogue, const PolicyParams& p) {
  std::string trust_why;
  const bool trusted = order_trusted(trust, p, trust_why);
  const int root = s.root_cause;
  // What acting on a failing channel j would do for the alarmed one, when that claim may be made.
  auto support_note = [&](int j, AdviceItem& claimed) -> std::string {
    for (const auto& c : candidates) {
      if (c.intervene != j) continue;
      claimed = c;
      const std::string problem = claim_problem(s, c, false, trusted, trust_why, p);
      if (problem.empty()) {
        return "Bringing " + name_of(s, j) + " back to its baseline is predicted to change " + name_of(s, s.target) +
               " by " + effect_text(c, p) + " " + when_text(c, s) + ".";
      }
      claimed.reliable = false;
      return "Effect on " + name_of(s, s.target) + " not claimed: " + problem + ".";
    }
    return "";
  };
  if (root >= 0 && root != s.target && is_failing(s, root)) {
    // The alarmed channel follows a failing root cause: fix the root cause, never "reduce it to help".
    AdviceItem claimed;
    const std::string note = support_note(root, claimed);
    return act_on_asset(s, root, catalogue, note.empty() ? nullptr : &claimed, note);
  }
  Decision d;
  std::string first_problem;
  for (const auto& c : candidates) {
    const std::string problem = claim_problem(s, c, false, trusted, trust_why, p);
    if (!problem.empty()) {
      if (first_problem.empty()) first_problem = problem;
      continue;
    }
    if (is_failing(s, c.intervene)) {
      // A reliable driver that is failing itself (an open alarm at this severity or worse): act on it as an
      // asset, quoting what fixing it does for the alarmed channel; never "reduce it to help".
      if (!d.items.empty()) continue;
      AdviceItem claimed;
      const std::string note = name_of(s, c.intervene) + " drives " + name_of(s, s.target) + " and is failing itself. " +
                               support_note(c.intervene, claimed);
      return act_on_asset(s, c.intervene, catalogue, &claimed, note);
    }
    AdviceItem item = c;
    item.rank = static_cast<int>(d.items.size()) + 1;
    const std::string action = "Reduce " + name_of(s, c.intervene) + " by " + c.reduction +
                               " back to its baseline (upstream lever for " + name_of(s, s.target) +
                               "): predicted change of " + name_of(s, s.target) + " " + effect_text(c, p) + " " +
                               when_text(c, s) + ".";
    if (d.items.empty()) {
      d.kind = "upstream_lever";
      d.act_on = c.intervene;
      d.action = action;
    }
    item.text = action + " Model: " + c.summary + ".";
    item.action = action;
    d.items.push_back(std::move(item));
  }
  if (!d.items.empty()) return d;
  const std::string why = !first_problem.empty() ? first_problem : advisor_why.empty() ? "no candidate" : advisor_why;
  const std::string own = root == s.target ? "Root cause is " + name_of(s, s.target) + " itself; no upstream lever: "
                                           : "No upstream lever: ";
  return act_on_asset(s, s.target, catalogue, nullptr, own + why + ".");
}

}  // namespace causal::advice
