// One field list per recorded message type: the columns of its CSV file and historian table (docs/historian.md),
// in order, each tied to the message field it holds. causal-recorder writes a row from it and twin-web reads a
// history row back into the message from the same list, so the two sides cannot drift apart column by column.
//
// MessageFields<M>::table names M's historian table; MessageFields<M>::list(io, m) is M's list, called with a
// writer (m const: the row's cells are made from m) or a reader (m filled from a row). What a column means is
// said by the io call; how it is spelt is the io's:
//   io.text(name, s)              a string field as it is
//   io.integer(name, v)           any integer field
//   io.real(name, v)              a double
//   io.hours(name, v, known)      hours; empty when unknown (NaN) or when `known` is false
//   io.flag(name, b)              true | false
//   io.utc(name, ns)              a UTC time field as text; empty for 0 (not set)
//   io.named(name, e, present)    an enum by its name; empty when `present` is false (the reader then leaves e)
//   io.utc_copy(name, ns)         an integer time field written once more as UTC text (written, never read back)
//   io.derived(name, cell)        a column the writer computes from more than the message (never read back)
// Appending a field to a message means appending one line here, at the end of its list (the CSV files keep their
// column order; a recorder restarted on an older file moves it aside, causal/io/csv_format.hpp).
#pragma once

#include "causal_twin.h"

#include <string>

namespace causal::dds {

template <class Message>
struct MessageFields;  // one specialisation per recorded message type

// alarms.csv / alarms: one row per alarm event. event_utc (writer only): the data time of this state change (the
// caller knows it; record_rows.hpp says how).
template <>
struct MessageFields<causal_twin::Alarm> {
  static constexpr const char* table = "alarms";
  template <class IO, class M>
  static void list(IO& io, M& a, const std::string& event_utc = {}) {
    io.text("alarm_id", a.alarm_id());
    io.named("state", a.state());
    io.named("severity", a.severity());
    io.text("kind", a.kind());
    io.text("asset_group", a.asset_group());
    io.integer("channel", a.channel());
    io.text("channel_name", a.channel_name());
    io.integer("sample_index", a.sample_index());
    io.derived("time_utc", event_utc);
    io.utc("raised_utc", a.raised_time_ns());
    io.utc("cleared_utc", a.cleared_time_ns());
    io.integer("root_cause_channel", a.root_cause_channel());
    io.text("root_cause_name", a.root_cause_name());
    io.real("score", a.score());
    io.real("threshold", a.threshold());
    io.text("reason", a.reason());
    // appended: degradation, data_quality, health or operating_change; the root-cause attribution's confidence
    io.text("category", a.category());
    io.real("root_cause_confidence", a.root_cause_confidence());
    // appended later: the next level ahead of a degradation alarm and the predicted hours to it (median, 90 %
    // interval), read only when next_level is set (the IDL says so)
    io.text("next_level", a.next_level());
    const bool ahead = !a.next_level().empty();
    io.hours("hours_to_next_level", a.hours_to_next_level(), ahead);
    io.hours("hours_to_next_level_low", a.hours_to_next_level_low(), ahead);
    io.hours("hours_to_next_level_high", a.hours_to_next_level_high(), ahead);
  }
};

// recommendations.csv / recommendations: every field of Recommendation, in IDL order.
template <>
struct MessageFields<causal_twin::Recommendation> {
  static constexpr const char* table = "recommendations";
  template <class IO, class M>
  static void list(IO& io, M& r) {
    io.text("recommendation_id", r.recommendation_id());
    io.text("alarm_id", r.alarm_id());
    io.text("asset_group", r.asset_group());
    io.integer("rank", r.rank());
    io.integer("target_channel", r.target_channel());
    io.integer("intervene_channel", r.intervene_channel());
    io.real("delta", r.delta());
    io.real("effect_immediate", r.effect_immediate());
    io.real("effect_steady_state", r.effect_steady_state());
    io.real("effect_low", r.effect_low());
    io.real("effect_high", r.effect_high());
    io.real("confidence", r.confidence());
    io.text("text", r.text());
    // appended later: stability and units of the answer
    io.text("answer_kind", r.answer_kind());
    io.integer("horizon_snapshots", r.horizon_snapshots());
    io.real("spectral_radius", r.spectral_radius());
    io.integer("draws", r.draws());
    io.integer("unstable_draws", r.unstable_draws());
    io.real("unstable_draw_share", r.unstable_draw_share());
    io.real("effect_median", r.effect_median());
    io.real("effect_percent", r.effect_percent());
    io.real("effect_percent_low", r.effect_percent_low());
    io.real("effect_percent_high", r.effect_percent_high());
    io.real("effect_level_change", r.effect_level_change());
    io.flag("reliable", r.reliable());
    io.text("summary", r.summary());
    // appended later: the alarm event it answers (raise or escalation) and the decision
    io.integer("sample_index", r.sample_index());
    io.text("action", r.action());
    io.text("action_kind", r.action_kind());
    io.integer("act_on_channel", r.act_on_channel());
    io.text("act_on_name", r.act_on_name());
    io.real("horizon_hours", r.horizon_hours());
    io.real("order_confidence", r.order_confidence());
    io.text("order_source", r.order_source());
  }
};

// prognosis.csv / prognoses: the prognosis interface first (channel 1-based, level warning | critical |
// end_of_life, empty hours = unknown), then the rest of the message.
template <>
struct MessageFields<causal_twin::Prognosis> {
  static constexpr const char* table = "prognoses";
  template <class IO, class M>
  static void list(IO& io, M& p) {
    io.text("asset_group", p.asset_group());
    io.integer("channel", p.channel());
    io.text("channel_name", p.channel_name());
    io.integer("sample_index", p.sample_index());
    io.utc("time_utc", p.time_ns());
    io.text("level", p.level());
    io.hours("hours", p.hours(), true);
    io.hours("hours_low", p.hours_low(), true);
    io.hours("hours_high", p.hours_high(), true);
    io.flag("known", p.known());
    io.flag("reached", p.reached());
    io.real("level_ratio", p.level_ratio());
    io.real("current_ratio", p.current_ratio());
    io.real("growth_per_hour", p.growth_per_hour());
    io.real("coverage", p.coverage());
    io.utc("eta_utc", p.eta_time_ns());
    io.utc("eta_low_utc", p.eta_low_time_ns());
    io.utc("eta_high_utc", p.eta_high_time_ns());
    io.text("alarm_id", p.alarm_id());
    io.text("text", p.text());
  }
};

// asset_status.csv / asset_status: every field of AssetStatus, in IDL order.
template <>
struct MessageFields<causal_twin::AssetStatus> {
  static constexpr const char* table = "asset_status";
  template <class IO, class M>
  static void list(IO& io, M& s) {
    io.text("asset_group", s.asset_group());
    io.text("state", s.state());
    io.integer("learning_seen", s.learning_seen());
    io.integer("learning_needed", s.learning_needed());
    io.integer("sample_index", s.sample_index());
    io.utc("time_utc", s.time_ns());
    io.flag("has_alarm", s.has_alarm());
    io.named("worst_severity", s.worst_severity(), s.has_alarm());  // meaningful only with an open alarm
    io.integer("open_alarms", s.open_alarms());
    io.integer("root_cause_channel", s.root_cause_channel());
    io.text("root_cause_name", s.root_cause_name());
    io.text("action", s.action());
    io.text("prognosis_text", s.prognosis_text());
    io.text("text", s.text());
    io.integer("unacknowledged_alarms", s.unacknowledged_alarms());
    io.integer("shelved_alarms", s.shelved_alarms());
    io.integer("alarms_per_10_min", s.alarms_per_10_min());
    io.flag("alarm_flood", s.alarm_flood());
    io.integer("standing_alarms", s.standing_alarms());
    io.integer("chattering_alarms", s.chattering_alarms());
  }
};

// alarm_actions.csv / alarm_actions: an applied alarm action (until is 0 but for a shelving).
template <>
struct MessageFields<causal_twin::AlarmActionResult> {
  static constexpr const char* table = "alarm_actions";
  template <class IO, class M>
  static void list(IO& io, M& r) {
    io.text("action_id", r.request_id());
    io.text("asset_group", r.asset_group());
    io.text("alarm_id", r.alarm_id());
    io.named("action", r.action());
    io.text("user_name", r.user_name());
    io.text("reason", r.reason());
    io.utc("time_utc", r.time_ns());
    io.utc("until_utc", r.until_ns());
    io.integer("time_ns", r.time_ns());
    io.integer("until_ns", r.until_ns());
  }
};

// interventions.csv / interventions: every field of Intervention, in IDL order, its times also as UTC.
template <>
struct MessageFields<causal_twin::Intervention> {
  static constexpr const char* table = "interventions";
  template <class IO, class M>
  static void list(IO& io, M& i) {
    io.text("request_id", i.request_id());
    io.text("asset_group", i.asset_group());
    io.integer("channel", i.channel());
    io.real("change_percent", i.change_percent());
    io.integer("start_snapshot_index", i.start_snapshot_index());
    io.integer("start_time_ns", i.start_time_ns());
    io.utc_copy("start_utc", i.start_time_ns());
    io.integer("duration_snapshots", i.duration_snapshots());
    io.text("recommendation_id", i.recommendation_id());
    io.integer("target_channel", i.target_channel());
    io.text("approved_by", i.approved_by());
    io.integer("approved_time_ns", i.approved_time_ns());
    io.utc_copy("approved_utc", i.approved_time_ns());
  }
};

// intervention_outcomes.csv / intervention_outcomes: every field of InterventionOutcome, in IDL order.
template <>
struct MessageFields<causal_twin::InterventionOutcome> {
  static constexpr const char* table = "intervention_outcomes";
  template <class IO, class M>
  static void list(IO& io, M& o) {
    io.text("request_id", o.request_id());
    io.text("asset_group", o.asset_group());
    io.text("recommendation_id", o.recommendation_id());
    io.integer("channel", o.channel());
    io.integer("target_channel", o.target_channel());
    io.integer("start_snapshot_index", o.start_snapshot_index());
    io.integer("end_snapshot_index", o.end_snapshot_index());
    io.text("status", o.status());
    io.real("predicted_percent", o.predicted_percent());
    io.real("predicted_percent_low", o.predicted_percent_low());
    io.real("predicted_percent_high", o.predicted_percent_high());
    io.real("confidence", o.confidence());
    io.real("observed_percent", o.observed_percent());
    io.flag("inside", o.inside());
    io.flag("improved", o.improved());
    io.real("lever_trust", o.lever_trust());
    io.flag("lever_claimed", o.lever_claimed());
    io.text("text", o.text());
  }
};

}  // namespace causal::dds
