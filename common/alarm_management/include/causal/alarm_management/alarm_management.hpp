// Alarm management after ISA-18.2 / IEC 62682: operators acknowledge and shelve alarms, shelving expires by itself,
// and the alarm system's health is measured (floods, standing and chattering alarms, shelved alarms).
// Middleware-free (std only): alarm-recommender feeds it the alarm events it publishes and the operators' actions,
// and publishes what it returns.
//
// Two clocks, on purpose:
//  * Acknowledging and shelving are operator actions: their times, the shelving's end and its expiry are wall-clock
//    UTC (`now_ns` is passed in by the caller, so a test chooses it and expiry is deterministic).
//  * The health figures describe the alarm stream: they are counted in data time (the alarms' raise and clear
//    times, the group's latest observation), so a replayed recording gives the same figures at any speed.
//
// What an action applies to:
//  * ACKNOWLEDGE: one alarm id. It holds until the alarm escalates (a worse severity must be seen again) or a new
//    alarm is raised (a new id).
//  * SHELVE / UNSHELVE: the alarm's source, i.e. its id without the trailing "/<counter>" (asset group, channel,
//    detector): the engine numbers every raise anew, and a nuisance source must stay shelved across its raises.
//    While shelved, the source's events are still published and recorded, flagged `shelved`, not annunciated.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace causal::estimation {
class StateWriter;  // causal/estimation/state_archive.hpp (causal_core: std + Eigen)
class StateReader;
}  // namespace causal::estimation

namespace causal::alarm_management {

enum class ActionKind { Acknowledge, Shelve, Unshelve };
// "acknowledge" | "shelve" | "unshelve"; parse_action is the inverse.
const char* to_string(ActionKind kind);
[[nodiscard]] std::optional<ActionKind> parse_action(std::string_view text);

struct ActionRequest {
  std::string request_id;
  std::string asset_group;
  std::string alarm_id;
  ActionKind action = ActionKind::Acknowledge;
  std::string user;
  std::string reason;
  std::int64_t time_ns = 0;   // when the operator acted (UTC ns, wall clock)
  std::int64_t until_ns = 0;  // SHELVE: shelved until (UTC ns); 0 otherwise
};

// Why an action was refused (counted per reason).
enum class Refusal { None, BadRequest, UnknownAlarm, NotApplicable };
const char* to_string(Refusal refusal);  // "none" | "bad_request" | "unknown_alarm" | "not_applicable"

struct ActionOutcome {
  bool applied = false;
  Refusal refusal = Refusal::None;
  std::string error;          // why refused, for the operator
  bool acknowledged = false;  // the alarm's state after the action
  bool shelved = false;
  bool repeated = false;      // the request id was seen before: its first outcome, nothing applied again
};

// One alarm event as published (data time).
enum class EventState { Raised, Escalated, Cleared };
struct AlarmEventView {
  std::string alarm_id;
  std::string asset_group;
  EventState state = EventState::Raised;
  std::int64_t raised_time_ns = 0;   // data time of the raise
  std::int64_t cleared_time_ns = 0;  // data time of the clear (Cleared only)
};

// The management flags an event is published with.
struct EventFlags {
  bool acknowledged = false;
  bool shelved = false;
};

// A shelving that ran out (wall clock): published like an UNSHELVE by the service.
struct ExpiredShelve {
  std::string asset_group;
  std::string source;      // alarm id without its counter
  std::string alarm_id;    // the id the shelve was requested on
  std::int64_t until_ns = 0;
};

struct GroupHealth {
  unsigned unacknowledged = 0;     // open alarms not acknowledged since their raise or latest escalation
  unsigned shelved = 0;            // shelved sources
  unsigned alarms_per_10_min = 0;  // raises in (t - 10 min, t] of data time
  bool flood = false;              // alarms_per_10_min > flood_above
  unsigned standing = 0;           // open alarms raised more than 24 h of data time before t
  unsigned chattering = 0;         // sources with >= 3 raises in (t - 60 s, t] of data time
  unsigned open = 0;               // open alarms (every category)
};

// The ISA-18.2 figures (their usual values) and the bounds on operator input. Not read from a file: they are the
// standard's definitions, not plant tuning.
struct ManagementLimits {
  std::int64_t flood_window_ns = 600'000'000'000;          // 10 min
  unsigned flood_above = 10;                               // more than 10 alarms per 10 min and operator
  std::int64_t standing_after_ns = 86'400'000'000'000;     // 24 h
  std::int64_t chatter_window_ns = 60'000'000'000;         // 1 min
  unsigned chatter_raises = 3;                             // 3 raise/clear cycles within it
  std::int64_t max_shelve_ns = 7 * 86'400'000'000'000LL;   // shelving is time-limited (ISA-18.2 11.5): a week
  std::size_t max_text = 255;                              // user, reason, ids: longest accepted (a DDS id)
  std::size_t remembered_requests = 4096;                  // request ids kept to answer a re-delivered request
  std::size_t remembered_cleared = 4096;                   // cleared alarms kept (acknowledge after clear)
};

struct ActionCounters {
  std::uint64_t applied = 0;
  std::uint64_t repeated = 0;
  std::map<Refusal, std::uint64_t> refused;
  std::uint64_t expired = 0;
};

// "<group>/<channel>/<kind>/<counter>" -> "<group>/<channel>/<kind>" (an id without '/' is its own source).
std::string source_of(const std::string& alarm_id);

class AlarmManager {
 public:
  explicit AlarmManager(ManagementLimits limits = {});

  // An event the service publishes: updates the alarm's state and the health history; returns its flags.
  EventFlags on_event(const AlarmEventView& event);
  // The flags of an alarm as held now (for republishing), without changing anything.
  EventFlags flags(const std::string& alarm_id) const;
  // An event published again after a restart (the engine checkpoint's last event per alarm id): an alarm this
  // manager already holds in the same open/cleared state keeps its acknowledgement and its raise history (on_event
  // would take a republished raise or escalation for a new one and clear the acknowledgement); any other is
  // on_event.
  EventFlags on_republished(const AlarmEventView& event);

  // An operator's action at wall-clock time now_ns. Refused (nothing changes) on a malformed request, an unknown
  // alarm id or an alarm of another group, an action that does not apply (acknowledge an acknowledged alarm,
  // unshelve what is not shelved), a shelving end not after now or beyond max_shelve_ns.
  ActionOutcome apply(const ActionRequest& request, std::int64_t now_ns);

  // Shelvings whose end is at or before now_ns (wall clock), lifted and returned in (until, source) order.
  std::vector<ExpiredShelve> expire(std::int64_t now_ns);

  // The group's figures at data time t_ns (usually its latest observation).
  GroupHealth health(const std::string& asset_group, std::int64_t t_ns) const;

  const ActionCounters& counters() const { return counters_; }

  // Checkpoint (crash and restart safety): the alarms held (acknowledged or not, open or cleared), the shelvings
  // with their wall-clock end (an expiry after a restart happens at the same time as without it), the raise
  // histories of the health figures and the remembered request outcomes (a request re-delivered after a restart
  // is answered with its first outcome, not applied twice). One tagged section "alarm_management" (version 1).
  // The counters are not saved: they count this process's work (its summary line). restore() replaces the state
  // and throws estimation::StateError on a section of another tag or version or a truncated one.
  void save(estimation::StateWriter& out) const;
  void restore(estimation::StateReader& in);
  const ManagementLimits& limits() const { return limits_; }

 private:
  struct AlarmRecord {
    std::string asset_group;
    bool open = true;
    bool acknowledged = false;
    std::int64_t raised_time_ns = 0;
  };
  struct Shelving {
    std::string asset_group;
    std::string alarm_id;
    std::int64_t until_ns = 0;
  };
  ActionOutcome refuse(Refusal why, std::string error);
  ActionOutcome act(const ActionRequest& request, AlarmRecord& alarm, std::int64_t now_ns);
  void remember(const std::string& request_id, const ActionOutcome& outcome);
  void forget_old_cleared();
  // The checkpoint's field list (alarm_management_state.cpp): M is AlarmManager, const when saving.
  template <class Io, class M>
  static void fields(Io io, M& m);

  ManagementLimits limits_;
  std::map<std::string, AlarmRecord> alarms_;            // by alarm id
  std::deque<std::string> cleared_order_;                // cleared ids, oldest first (bounded)
  std::map<std::string, Shelving> shelved_;              // by source
  std::map<std::pair<std::string, std::string>, std::vector<std::int64_t>> raises_by_source_;  // (group, source):
                                                                     // raise times, within the chatter window
  std::map<std::string, std::vector<std::int64_t>> raises_by_group_;   // raise times, within the flood window
  std::map<std::string, ActionOutcome> outcomes_;        // by request id (bounded)
  std::deque<std::string> outcome_order_;
  ActionCounters counters_;
};

}  // namespace causal::alarm_management
