// The decision published with every degradation alarm event (raise and escalation): which asset to act on
// and what to do. Pure function of the alarm, the open alarms, the advisor's ranked candidates, how far the
// causal order can be trusted and the action catalogue, so it is unit-tested without DDS.
//
// Rules (docs/advice.md "From alarm to action"):
//  * A channel is FAILING when it has an open degradation alarm at this event's severity or worse. A failing
//    channel is never offered as a lever to help another channel: the failing one is what to act on.
//  * A lever claim on a candidate needs: the advisor's candidate reliable (its interval excludes "no
//    change"), an interval spanning at most max_interval_factor in level ("effect unknown" beyond), and a
//    trusted causal order (configured graph, or learned with order_confidence >= min_order_confidence).
//  * The root cause is another, failing channel: act on the root cause (act_on_asset, the catalogue's
//    actions for its type and the event's severity), quoting its effect on the alarmed channel if claimable.
//  * Else the best claimable candidate: a healthy one is an upstream lever (upstream_lever: reduce it, with
//    its predicted effect); a failing one is acted on as an asset (act_on_asset, with that effect quoted).
//  * No claimable candidate (the alarmed channel is its own root cause in the sense of the issue: no lever
//    whose interval excludes "no change"): act on the alarmed channel and say why no lever is claimed.
#pragma once

#include "causal/advice/action_catalogue.hpp"
#include "causal/advice/advisor.hpp"

#include "causal/alarms/alarm_event.hpp"
#include "causal/analysis/effect_units.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace causal::advice {

struct PolicyParams {
  double min_order_confidence = 0.8;   // learned order: bootstrap stability needed for a lever claim
  double max_interval_factor = analysis::kMaxKnownLevelFactor;  // wider 90 % interval in level: "effect unknown"
};

struct OrderTrust {
  double confidence = NAN;  // CausalFactorBatch.order_confidence (NaN: not assessed)
  std::string source;       // "learned", "configured", "untrusted" or "" (not assessed)
};

// True when lever claims may be made on this order; `why` says why not.
bool order_trusted(const OrderTrust& t, const PolicyParams& p, std::string& why);

struct AlarmSituation {
  std::string asset_group;
  std::vector<std::string> channel_names;
  int target = 0;                              // 0-based alarmed channel
  alarms::Severity severity = alarms::Severity::Advisory;
  int root_cause = -1;                         // 0-based, -1 unknown
  std::vector<alarms::AlarmEvent> open_alarms; // the engine's active alarms (after this event)
  double snapshot_hours = NAN;                 // the group's snapshot cadence (NaN unknown)
  std::int64_t time_ns = 0;                    // data time of the event
};

struct Decision {
  std::string kind = "act_on_asset";  // "act_on_asset" or "upstream_lever"
  int act_on = 0;                     // 0-based channel to act on
  std::string action;                 // what to do, on which asset (never empty)
  std::string note;                   // why no lever is claimed / what the advisor found (may be empty)
  std::vector<AdviceItem> items;      // to publish, rank 1 first (never empty); text = action [+ note]
};

bool is_failing(const AlarmSituation& s, int channel);

// candidates: the advisor's ranked candidates (Advisor::evaluate), possibly empty (advisor_why says why).
Decision decide(const AlarmSituation& s, const std::vector<AdviceItem>& candidates, const std::string& advisor_why,
                const OrderTrust& trust, const ActionCatalogue& catalogue, const PolicyParams& p);

// "2.0 h" / "3.5 days"; "?" when not finite.
std::string hours_text(double hours);

}  // namespace causal::advice
