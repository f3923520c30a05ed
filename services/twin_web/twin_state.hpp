// What twin-web knows about the running twin: per asset group the condition trend (bounded), the latest
// condition-level filter factors of every outcome, the alarms and the recommendations. The DDS thread writes it
// (on_*), the web threads read it (json(), wait_for_change()); one mutex guards it and the web side only ever
// sees a serialised copy, so a slow browser never holds up a DDS reader. Bad input is refused and counted, never
// stored: a non-finite value in a trend, a vector whose channel count differs from its group's.
#pragma once

#include "causal_twin.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace causal::web {

// Links at least this many standard deviations from zero are drawn in the causal graph (as in causal-report).
inline constexpr double kSignificantZ = 2.0;

struct StateLimits {
  std::size_t trend_points = 2000;     // per asset group; the oldest point is forgotten first
  std::size_t closed_alarms = 200;     // per asset group; open alarms are always kept
  std::size_t recommendations = 200;   // per asset group; the oldest is forgotten first
  std::size_t interventions = 100;     // per asset group (approvals with their outcomes); the oldest is forgotten first
};

struct TrendPoint {
  std::uint64_t index = 0;  // snapshot index from the source
  std::int64_t time_ns = 0;
  std::vector<double> values;  // one per channel, finite
};

struct OutcomeFactors {
  std::uint64_t index = 0;
  std::int64_t time_ns = 0;
  int channel_count = 0;  // G of the model (decides how factor names are spelled)
  std::vector<std::string> names;
  std::vector<double> values, stddev;
};

// One link of the causal graph: channel `from` drives channel `to` (1-based) at lag `lag` (0 = at once).
struct CausalEdge {
  int from = 0, to = 0, lag = 0;
  double factor = 0.0, stddev = 0.0, z = 0.0;  // z = factor / stddev
};

struct CausalGraph {
  std::uint64_t index = 0;           // newest snapshot index among the outcomes' factors
  std::vector<CausalEdge> edges;     // every cross link (from != to) with a usable standard deviation
  std::vector<CausalEdge> self_lags; // from == to: a channel's own past
  std::size_t unusable = 0;          // factors with an unknown name, a non-finite value or std <= 0
};

struct AlarmView {
  causal_twin::Alarm last;                    // the latest event of this alarm id
  std::uint64_t raised_index = 0;             // snapshot index when it was raised
  std::optional<std::uint64_t> cleared_index; // snapshot index when it cleared
  std::uint64_t arrival = 0;                  // order of its latest event, for "oldest closed first"
  // Alarm management (ISA-18.2): from the alarm's own events (their flags) and the operators' applied actions.
  bool acknowledged = false;
  std::string acknowledged_by;
  bool shelved = false;
  std::int64_t shelved_until_ns = 0;  // 0: unknown (only the event's flag was seen)
  std::string shelved_by, shelve_reason;
  bool open() const { return last.state() != causal_twin::CLEARED; }
};

struct RecommendationView {
  causal_twin::Recommendation last;
  std::uint64_t arrival = 0;
};

// The closed loop (twin_state_interventions.cpp): an approved intervention (causal_twin/intervention) and, after its
// window, the twin's check of it (causal_twin/intervention_outcome), joined by request id. Either may come first.
struct InterventionView {
  std::optional<causal_twin::Intervention> approval;
  std::optional<causal_twin::InterventionOutcome> outcome;
  std::uint64_t arrival = 0;  // order of its latest message, for "oldest forgotten first" and the page's order
};

struct GroupState {
  std::uint64_t version = 0;  // bumped by every change of this group
  std::string feature;
  std::vector<std::string> channels;
  std::deque<TrendPoint> trend;                 // sorted by index
  // Snapshot indices skipped by a newer point and not come since (input lost upstream; a late one fills its hole):
  // the gaps the view has, counted.
  std::uint64_t missing = 0;
  std::map<int, OutcomeFactors> factors;        // condition-level filter, by 1-based outcome
  std::map<std::string, AlarmView> alarms;      // by alarm id
  std::map<std::string, RecommendationView> recommendations;  // by recommendation id
  // The recommender's operator line (causal_twin/asset_status): learning n of N, healthy, stopped, alarm.
  std::optional<causal_twin::AssetStatus> status;
  // The latest time-to-level forecast (causal_twin/prognosis) by 1-based channel and level name.
  std::map<std::pair<int, std::string>, causal_twin::Prognosis> prognoses;
  std::map<std::string, InterventionView> interventions;  // by request id
};

struct StateCounters {
  std::uint64_t condition_vectors = 0;   // received
  std::uint64_t duplicates = 0;          // a snapshot index the trend already has (re-sent after a restart)
  std::uint64_t rejected_vectors = 0;    // non-finite value, or a channel count that differs from the group's
  std::uint64_t trend_points_forgotten = 0;  // beyond StateLimits::trend_points
  std::uint64_t snapshots_missing = 0;   // sum of GroupState::missing: gaps in the trends (lost upstream)
  std::uint64_t factor_messages = 0;     // condition-level filter messages (batches) used for the graph
  std::uint64_t factor_messages_skipped = 0;   // other estimators and time scales (not drawn)
  std::uint64_t factor_messages_rejected = 0;  // inconsistent batches (outcome range, names/values/std lengths)
  std::uint64_t alarm_events = 0;
  std::uint64_t recommendations = 0;
  std::uint64_t statuses = 0;
  std::uint64_t prognoses = 0;
  std::uint64_t prognoses_stale = 0;
  std::uint64_t alarm_actions = 0;          // applied action results received
  std::uint64_t alarm_actions_refused = 0;  // refused ones (nothing changed)  // older than the one held for that channel and level (re-sent), not kept
  std::uint64_t interventions = 0;           // approvals received
  std::uint64_t intervention_outcomes = 0;   // outcomes received
  std::uint64_t interventions_forgotten = 0; // beyond StateLimits::interventions (approval and outcome together)
};

// The causal graph of one group from its outcomes' latest factors (names parsed by the project's convention).
CausalGraph causal_graph(const GroupState& group);

class TwinState {
 public:
  explicit TwinState(StateLimits limits = {});

  // DDS thread.
  void on_condition(const causal_twin::ConditionVector& in);
  void on_factors(const causal_twin::CausalFactorBatch& in);  // one message: every outcome at one index
  void on_alarm(const causal_twin::Alarm& in);
  void on_recommendation(const causal_twin::Recommendation& in);
  void on_status(const causal_twin::AssetStatus& in);
  void on_prognosis(const causal_twin::Prognosis& in);
  // An applied alarm action (twin_state_actions.cpp): acknowledged by whom, shelved until when; refused ones are
  // counted only.
  void on_action_result(const causal_twin::AlarmActionResult& in);
  // The closed loop (twin_state_interventions.cpp): an approval and the twin's check of it, kept per request id.
  void on_intervention(const causal_twin::Intervention& in);
  void on_intervention_outcome(const causal_twin::InterventionOutcome& in);

  // Any thread.
  std::uint64_t version() const;
  // Waits until the version differs from `seen` (true) or the timeout passes (false).
  bool wait_for_change(std::uint64_t seen, std::chrono::milliseconds timeout) const;
  // The whole state as JSON (see state_json.cpp), built once per version and shared.
  std::shared_ptr<const std::string> json() const;

  // What one page shows, so that a plant of many asset groups does not send every group to every page: the
  // overview (every group's id, channels, open alarms; changes when a group appears or an alarm changes) and
  // one group in full. Versions of the two parts; a page is current when it has both.
  struct Versions {
    std::uint64_t overview = 0, group = 0;
    bool operator==(const Versions& o) const { return overview == o.overview && group == o.group; }
    bool operator!=(const Versions& o) const { return !(*this == o); }
  };
  Versions versions(const std::string& asset_group) const;
  bool wait_for_change(const std::string& asset_group, Versions seen, std::chrono::milliseconds timeout) const;
  // {"version": "<overview>.<group>", "overview": {...}, "group": {...} | null}; parts cached per version.
  std::string page_json(const std::string& asset_group) const;
  // The group a page without ?group= shows: the first with a condition trend, else the first known, else "".
  std::string default_group() const;
  // Channel names of a group (empty when the group is unknown or has sent no condition vector yet).
  std::vector<std::string> channels(const std::string& asset_group) const;
  StateCounters counters() const;
  // A copy of one group, for tests and diagnostics.
  std::optional<GroupState> group(const std::string& asset_group) const;

  // Something that is not the twin's data but belongs on the page (domain, service name).
  void set_info(std::string key, std::string value);

 private:
  GroupState& group_locked(const std::string& asset_group);
  void changed_locked(GroupState* group = nullptr, bool overview = false);
  Versions versions_locked(const std::string& asset_group) const;
  std::uint64_t index_of_time_locked(const GroupState& g, std::int64_t time_ns, std::uint64_t fallback) const;
  InterventionView& intervention_locked(GroupState& g, const std::string& request_id);
  // An approval or the twin's check of it, kept in its slot of the request's view and counted.
  template <class M>
  void keep_intervention(const M& in, std::optional<M> InterventionView::*slot, std::uint64_t& received);

  StateLimits limits_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::map<std::string, GroupState> groups_;
  std::map<std::string, std::string> info_;
  StateCounters counters_;
  std::uint64_t version_ = 0;
  std::uint64_t overview_version_ = 0;
  std::uint64_t arrivals_ = 0;
  mutable std::uint64_t json_version_ = ~std::uint64_t{0};
  mutable std::shared_ptr<const std::string> json_;
  mutable std::uint64_t overview_json_version_ = ~std::uint64_t{0};
  mutable std::string overview_json_;
  mutable std::map<std::string, std::pair<std::uint64_t, std::string>> group_json_;  // by group: version, text
};

}  // namespace causal::web
