#include "record_rows.hpp"

#include "row_cells.hpp"

#include "causal/io/csv_format.hpp"
#include "causal/io/file_names.hpp"

#include "causal/dds/alarm_conversions.hpp"
#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/io/time_format.hpp"

namespace causal::recorder {

using io::format_integer;
using io::format_number;

namespace {
std::string utc_or_empty(std::int64_t time_ns) { return time_ns == 0 ? std::string() : io::format_utc(time_ns); }
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

std::vector<std::string> alarm_row(const causal_twin::Alarm& a, std::optional<std::int64_t> evidence_time_ns) {
  std::string event_time;
  switch (a.state()) {
    case causal_twin::CLEARED: event_time = utc_or_empty(a.cleared_time_ns()); break;
    case causal_twin::RAISED: event_time = utc_or_empty(a.raised_time_ns()); break;
    case causal_twin::ESCALATED: event_time = evidence_time_ns ? io::format_utc(*evidence_time_ns) : ""; break;
  }
  RowCells row;
  dds::MessageFields<causal_twin::Alarm>::list(row, a, event_time);
  return row.take_cells();
}

bool PrognosisLedger::accept(const causal_twin::Prognosis& p) {
  const std::string key = p.asset_group() + '\x1f' + std::to_string(p.channel()) + '\x1f' + p.level();
  auto [it, created] = last_.try_emplace(key, p.sample_index());
  if (created) return true;
  if (p.sample_index() <= it->second) return false;
  it->second = p.sample_index();
  return true;
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

std::string row_signature(const std::vector<std::string>& row) {
  std::string s;
  for (const auto& cell : row) s += cell + '\x1f';
  return s;
}

std::string recommendation_signature(const causal_twin::Recommendation& r) { return row_signature(row_of(r)); }

std::string asset_status_signature(const causal_twin::AssetStatus& s) { return row_signature(row_of(s)); }

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
