#include "record_rows.hpp"

#include "causal/io/csv_format.hpp"
#include "causal/io/file_names.hpp"

#include "causal/dds/alarm_conversions.hpp"
#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/io/time_format.hpp"

#include <cmath>

namespace causal::recorder {

using io::format_integer;
using io::format_number;

namespace {
std::string utc_or_empty(std::int64_t time_ns) { return time_ns == 0 ? std::string() : io::format_utc(time_ns); }
// Hours: empty when unknown (NaN), as the interface says.
std::string hours_or_empty(double h) { return std::isfinite(h) ? format_number(h) : std::string(); }
}  // namespace

std::string conditions_file_name(const std::string& asset_group, const std::string& feature) {
  return "conditions_" + io::safe_file_component(asset_group) + "_" + io::safe_file_component(feature) + ".csv";
}

std::string factors_file_name(const std::string& asset_group, causal_twin::TimeScale scale,
                              causal_twin::EstimateKind kind) {
  return "factors_" + io::safe_file_component(asset_group) + "_" + dds::to_string(scale) + "_" + dds::to_string(kind) +
         ".csv";
}

std::vector<std::string> condition_header(const causal_twin::ConditionVector& in) {
  std::vector<std::string> h{"snapshot", "time_ns", "time_utc"};
  h.insert(h.end(), in.channel_names().begin(), in.channel_names().end());
  return h;
}

std::vector<std::string> condition_row(const causal_twin::ConditionVector& in) {
  std::vector<std::string> row{format_integer(static_cast<std::uint64_t>(in.snapshot_index())),
                               format_integer(static_cast<std::int64_t>(in.time_ns())), io::format_utc(in.time_ns())};
  const Eigen::VectorXd values = dds::values_of(in);
  for (Eigen::Index i = 0; i < values.size(); ++i) row.push_back(format_number(values[i]));
  return row;
}

const std::vector<std::string>& alarm_header() {
  static const std::vector<std::string> h{"alarm_id",      "state",        "severity",           "kind",
                                          "asset_group",   "channel",      "channel_name",       "sample_index",
                                          "time_utc",      "raised_utc",   "cleared_utc",        "root_cause_channel",
                                          "root_cause_name", "score",      "threshold",          "reason",
                                          // appended: degradation, data_quality, health or operating_change;
                                          // the root-cause attribution's confidence in [0, 1]
                                          "category", "root_cause_confidence",
                                          // appended later: the next level ahead of a degradation alarm and
                                          // the predicted hours to it (median, 90 % interval; empty = unknown)
                                          "next_level", "hours_to_next_level", "hours_to_next_level_low",
                                          "hours_to_next_level_high"};
  return h;
}

std::vector<std::string> alarm_row(const causal_twin::Alarm& a, std::optional<std::int64_t> evidence_time_ns) {
  std::string event_time;
  switch (a.state()) {
    case causal_twin::CLEARED: event_time = utc_or_empty(a.cleared_time_ns()); break;
    case causal_twin::RAISED: event_time = utc_or_empty(a.raised_time_ns()); break;
    case causal_twin::ESCALATED: event_time = evidence_time_ns ? io::format_utc(*evidence_time_ns) : ""; break;
  }
  return {a.alarm_id(),
          dds::to_string(a.state(), "?"),
          dds::to_string(a.severity(), "?"),
          a.kind(),
          a.asset_group(),
          format_integer(static_cast<std::uint64_t>(a.channel())),
          a.channel_name(),
          format_integer(static_cast<std::uint64_t>(a.sample_index())),
          event_time,
          utc_or_empty(a.raised_time_ns()),
          utc_or_empty(a.cleared_time_ns()),
          format_integer(static_cast<std::uint64_t>(a.root_cause_channel())),
          a.root_cause_name(),
          format_number(a.score()),
          format_number(a.threshold()),
          a.reason(),
          a.category(),
          format_number(a.root_cause_confidence()),
          a.next_level(),
          a.next_level().empty() ? std::string() : hours_or_empty(a.hours_to_next_level()),
          a.next_level().empty() ? std::string() : hours_or_empty(a.hours_to_next_level_low()),
          a.next_level().empty() ? std::string() : hours_or_empty(a.hours_to_next_level_high())};
}

const std::vector<std::string>& prognosis_header() {
  static const std::vector<std::string> h{"asset_group", "channel",   "channel_name", "sample_index", "time_utc",
                                          "level",       "hours",     "hours_low",    "hours_high",
                                          // after the interface columns: the rest of the message
                                          "known", "reached", "level_ratio", "current_ratio", "growth_per_hour",
                                          "coverage", "eta_utc", "eta_low_utc", "eta_high_utc", "alarm_id", "text"};
  return h;
}

std::vector<std::string> prognosis_row(const causal_twin::Prognosis& p) {
  return {p.asset_group(),
          format_integer(static_cast<std::uint64_t>(p.channel())),
          p.channel_name(),
          format_integer(static_cast<std::uint64_t>(p.sample_index())),
          utc_or_empty(p.time_ns()),
          p.level(),
          hours_or_empty(p.hours()),
          hours_or_empty(p.hours_low()),
          hours_or_empty(p.hours_high()),
          p.known() ? "true" : "false",
          p.reached() ? "true" : "false",
          format_number(p.level_ratio()),
          format_number(p.current_ratio()),
          format_number(p.growth_per_hour()),
          format_number(p.coverage()),
          utc_or_empty(p.eta_time_ns()),
          utc_or_empty(p.eta_low_time_ns()),
          utc_or_empty(p.eta_high_time_ns()),
          p.alarm_id(),
          p.text()};
}

bool PrognosisLedger::accept(const causal_twin::Prognosis& p) {
  const std::string key = p.asset_group() + '\x1f' + std::to_string(p.channel()) + '\x1f' + p.level();
  auto [it, created] = last_.try_emplace(key, p.sample_index());
  if (created) return true;
  if (p.sample_index() <= it->second) return false;
  it->second = p.sample_index();
  return true;
}

const std::vector<std::string>& recommendation_header() {
  static const std::vector<std::string> h{
      "recommendation_id", "alarm_id",    "asset_group",  "rank",       "target_channel", "intervene_channel", "delta",
      "effect_immediate",  "effect_steady_state", "effect_low", "effect_high", "confidence", "text",
      // appended later: stability and units of the answer
      "answer_kind", "horizon_snapshots", "spectral_radius", "draws", "unstable_draws", "unstable_draw_share",
      "effect_median", "effect_percent", "effect_percent_low", "effect_percent_high", "effect_level_change", "reliable",
      "summary",
      // appended later: the alarm event it answers (raise or escalation) and the decision
      "sample_index", "action", "action_kind", "act_on_channel", "act_on_name", "horizon_hours", "order_confidence",
      "order_source"};
  return h;
}

std::vector<std::string> recommendation_row(const causal_twin::Recommendation& r) {
  return {r.recommendation_id(),
          r.alarm_id(),
          r.asset_group(),
          format_integer(static_cast<std::uint64_t>(r.rank())),
          format_integer(static_cast<std::uint64_t>(r.target_channel())),
          format_integer(static_cast<std::uint64_t>(r.intervene_channel())),
          format_number(r.delta()),
          format_number(r.effect_immediate()),
          format_number(r.effect_steady_state()),
          format_number(r.effect_low()),
          format_number(r.effect_high()),
          format_number(r.confidence()),
          r.text(),
          r.answer_kind(),
          format_integer(static_cast<std::uint64_t>(r.horizon_snapshots())),
          format_number(r.spectral_radius()),
          format_integer(static_cast<std::uint64_t>(r.draws())),
          format_integer(static_cast<std::uint64_t>(r.unstable_draws())),
          format_number(r.unstable_draw_share()),
          format_number(r.effect_median()),
          format_number(r.effect_percent()),
          format_number(r.effect_percent_low()),
          format_number(r.effect_percent_high()),
          format_number(r.effect_level_change()),
          r.reliable() ? "true" : "false",
          r.summary(),
          format_integer(static_cast<std::uint64_t>(r.sample_index())),
          r.action(),
          r.action_kind(),
          format_integer(static_cast<std::uint64_t>(r.act_on_channel())),
          r.act_on_name(),
          format_number(r.horizon_hours()),
          format_number(r.order_confidence()),
          r.order_source()};
}

bool RepeatFilter::accept(const std::string& id, std::string signature) {
  auto [it, created] = last_.try_emplace(id, signature);
  if (created) return true;
  if (it->second == signature) return false;
  it->second = std::move(signature);
  return true;
}

std::string alarm_signature(const causal_twin::Alarm& a) {
  return std::string(dds::to_string(a.state(), "?")) + '\x1f' + dds::to_string(a.severity(), "?") + '\x1f' +
         std::to_string(a.sample_index());
}

std::string recommendation_signature(const causal_twin::Recommendation& r) {
  std::string s;
  for (const auto& cell : recommendation_row(r)) s += cell + '\x1f';
  return s;
}

std::string describe(const TopicCounts& c) {
  return "received " + std::to_string(c.received) + ", written " + std::to_string(c.written) + ", duplicates " +
         std::to_string(c.duplicates) + ", refused " + std::to_string(c.refused);
}

std::string describe_missing(const std::vector<dds::IndexRange>& missing, const std::string& unit) {
  if (missing.empty()) return {};
  return "lost " + unit + " " + dds::describe_ranges(missing);
}

void IndexClock::record(std::uint64_t index, std::int64_t time_ns) {
  times_[index] = time_ns;
  while (times_.size() > capacity_) times_.erase(times_.begin());
}

std::optional<std::int64_t> IndexClock::time_of(std::uint64_t index) const {
  const auto it = times_.find(index);
  if (it == times_.end()) return std::nullopt;
  return it->second;
}

}  // namespace causal::recorder
