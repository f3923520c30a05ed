#include "history_interventions.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace causal::web {

namespace {

using history::Row;

// Typed cells by column name; a missing column or an unparsable number throws (the row is then unreadable).
class RowCells {
 public:
  RowCells(const char* table, const Row& row) : t_(history::table(table)), r_(row) {}
  std::string text(const char* name) const { return cell(name).value_or(""); }
  double real(const char* name) const {
    const auto& c = cell(name);
    return c && !c->empty() ? std::stod(*c) : NAN;  // NULL: SQLite's NaN, unknown as on the topic
  }
  long long integer(const char* name) const {
    const auto& c = cell(name);
    if (!c || c->empty()) throw std::invalid_argument(std::string("no value in ") + name);
    return std::stoll(*c);
  }
  bool boolean(const char* name) const { return cell(name).value_or("") == "true"; }

 private:
  const history::Cell& cell(const char* name) const {
    const std::size_t i = t_.column(name);
    if (i == std::string::npos || i >= r_.size()) throw std::invalid_argument(std::string("no column ") + name);
    return r_[i];
  }
  const history::Table& t_;
  const Row& r_;
};

template <typename T>
std::optional<T> guarded(T (*make)(const Row&), const Row& row) {
  try {
    return make(row);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

causal_twin::Intervention make_intervention(const Row& row) {
  const RowCells c("interventions", row);
  causal_twin::Intervention i;
  i.request_id(c.text("request_id"));
  i.asset_group(c.text("asset_group"));
  i.channel(static_cast<std::uint16_t>(c.integer("channel")));
  i.change_percent(c.real("change_percent"));
  i.start_snapshot_index(static_cast<std::uint64_t>(c.integer("start_snapshot_index")));
  i.start_time_ns(c.integer("start_time_ns"));
  i.duration_snapshots(static_cast<std::uint32_t>(c.integer("duration_snapshots")));
  i.recommendation_id(c.text("recommendation_id"));
  i.target_channel(static_cast<std::uint16_t>(c.integer("target_channel")));
  i.approved_by(c.text("approved_by"));
  i.approved_time_ns(c.integer("approved_time_ns"));
  return i;
}

causal_twin::InterventionOutcome make_outcome(const Row& row) {
  const RowCells c("intervention_outcomes", row);
  causal_twin::InterventionOutcome o;
  o.request_id(c.text("request_id"));
  o.asset_group(c.text("asset_group"));
  o.recommendation_id(c.text("recommendation_id"));
  o.channel(static_cast<std::uint16_t>(c.integer("channel")));
  o.target_channel(static_cast<std::uint16_t>(c.integer("target_channel")));
  o.start_snapshot_index(static_cast<std::uint64_t>(c.integer("start_snapshot_index")));
  o.end_snapshot_index(static_cast<std::uint64_t>(c.integer("end_snapshot_index")));
  o.status(c.text("status"));
  o.predicted_percent(c.real("predicted_percent"));
  o.predicted_percent_low(c.real("predicted_percent_low"));
  o.predicted_percent_high(c.real("predicted_percent_high"));
  o.confidence(c.real("confidence"));
  o.observed_percent(c.real("observed_percent"));
  o.inside(c.boolean("inside"));
  o.improved(c.boolean("improved"));
  o.lever_trust(c.real("lever_trust"));
  o.lever_claimed(c.boolean("lever_claimed"));
  o.text(c.text("text"));
  return o;
}

}  // namespace

std::optional<causal_twin::Intervention> intervention_from_row(const Row& row) {
  return guarded(make_intervention, row);
}

std::optional<causal_twin::InterventionOutcome> intervention_outcome_from_row(const Row& row) {
  return guarded(make_outcome, row);
}

InterventionLoad load_interventions(history::HistoryStore& store, TwinState& state) {
  InterventionLoad out;
  for (const Row& r : store.select(history::table("interventions"), {})) {
    const auto x = intervention_from_row(r);
    x ? (state.on_intervention(*x), ++out.approvals) : ++out.unreadable;
  }
  for (const Row& r : store.select(history::table("intervention_outcomes"), {})) {
    const auto x = intervention_outcome_from_row(r);
    x ? (state.on_intervention_outcome(*x), ++out.outcomes) : ++out.unreadable;
  }
  return out;
}

}  // namespace causal::web
