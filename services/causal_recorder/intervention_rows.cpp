#include "intervention_rows.hpp"

#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <sstream>

namespace causal::recorder {

namespace {

using io::format_integer;
using io::format_number;

std::string utc_or_empty(std::int64_t ns) { return ns == 0 ? std::string() : io::format_utc(ns); }
std::string flag(bool b) { return b ? "true" : "false"; }

std::string joined(const std::vector<std::string>& cells) {
  std::string s;
  for (const auto& c : cells) s += c + '\x1f';
  return s;
}

}  // namespace

const std::vector<std::string>& intervention_header() {
  static const std::vector<std::string> h{"request_id", "asset_group", "channel", "change_percent",
                                          "start_snapshot_index", "start_time_ns", "start_utc", "duration_snapshots",
                                          "recommendation_id", "target_channel", "approved_by", "approved_time_ns",
                                          "approved_utc"};
  return h;
}

std::vector<std::string> intervention_row(const causal_twin::Intervention& in) {
  return {in.request_id(), in.asset_group(), format_integer(static_cast<std::uint64_t>(in.channel())),
          format_number(in.change_percent()), format_integer(static_cast<std::uint64_t>(in.start_snapshot_index())),
          format_integer(static_cast<std::int64_t>(in.start_time_ns())), utc_or_empty(in.start_time_ns()),
          format_integer(static_cast<std::uint64_t>(in.duration_snapshots())), in.recommendation_id(),
          format_integer(static_cast<std::uint64_t>(in.target_channel())), in.approved_by(),
          format_integer(static_cast<std::int64_t>(in.approved_time_ns())), utc_or_empty(in.approved_time_ns())};
}

const std::vector<std::string>& intervention_outcome_header() {
  static const std::vector<std::string> h{
      "request_id", "asset_group", "recommendation_id", "channel", "target_channel", "start_snapshot_index",
      "end_snapshot_index", "status", "predicted_percent", "predicted_percent_low", "predicted_percent_high",
      "confidence", "observed_percent", "inside", "improved", "lever_trust", "lever_claimed", "text"};
  return h;
}

std::vector<std::string> intervention_outcome_row(const causal_twin::InterventionOutcome& in) {
  return {in.request_id(), in.asset_group(), in.recommendation_id(),
          format_integer(static_cast<std::uint64_t>(in.channel())),
          format_integer(static_cast<std::uint64_t>(in.target_channel())),
          format_integer(static_cast<std::uint64_t>(in.start_snapshot_index())),
          format_integer(static_cast<std::uint64_t>(in.end_snapshot_index())), in.status(),
          format_number(in.predicted_percent()), format_number(in.predicted_percent_low()),
          format_number(in.predicted_percent_high()), format_number(in.confidence()),
          format_number(in.observed_percent()), flag(in.inside()), flag(in.improved()), format_number(in.lever_trust()),
          flag(in.lever_claimed()), in.text()};
}

InterventionTables::InterventionTables(dds::Participant& participant, const std::filesystem::path& out_dir,
                                       dds::EventLoop& loop, HistorySink* history)
    : interventions_(participant, dds::topics::kIntervention, dds::profiles::kInterventionReader),
      outcomes_(participant, dds::topics::kInterventionOutcome, dds::profiles::kInterventionOutcomeReader),
      intervention_file_(std::make_unique<io::CsvFile>(out_dir / kInterventionsFile, intervention_header())),
      outcome_file_(std::make_unique<io::CsvFile>(out_dir / kInterventionOutcomesFile, intervention_outcome_header())),
      history_(history),
      grants_(participant.directory(), "intervention", "approved intervention",
              "issue-identity.sh: an operator's grant names no partitions, or only those of --groups") {
  loop.attach(interventions_.get());
  loop.attach(outcomes_.get());
}

std::size_t InterventionTables::take() {
  // One instance per request id: a keyed reader hands them out instance by instance, so they are put back into
  // publication order (writer, sequence number) before writing.
  using Key = std::pair<std::string, std::uint64_t>;
  auto key_of = [](const eprosima::fastdds::dds::SampleInfo& info) {
    std::ostringstream w;
    w << info.sample_identity.writer_guid();
    return Key{w.str(), info.sample_identity.sequence_number().to64long()};
  };
  std::vector<std::pair<Key, causal_twin::Intervention>> ivs;
  std::vector<std::pair<Key, causal_twin::InterventionOutcome>> outs;
  interventions_.take_all([&](const auto& in, const auto& info) {
    if (grants_.entitled(in.asset_group(), info.sample_identity.writer_guid())) {
      ivs.emplace_back(key_of(info), in);
      return;
    }
    ++intervention_counts_.received;
    ++intervention_counts_.refused;
    spdlog::error("intervention {} (approved by '{}') not recorded: its writer may not approve for asset group '{}'",
                  in.request_id(), in.approved_by(), in.asset_group());
  });
  for (const auto& alarm : grants_.take_alarms()) spdlog::warn("HEALTH RAISED {}: {}", alarm.alarm_id(), alarm.reason());
  outcomes_.take_all([&](const auto& in, const auto& info) { outs.emplace_back(key_of(info), in); });
  auto by_key = [](const auto& x, const auto& y) { return x.first < y.first; };
  std::stable_sort(ivs.begin(), ivs.end(), by_key);
  std::stable_sort(outs.begin(), outs.end(), by_key);
  for (const auto& [k, in] : ivs) {
    ++intervention_counts_.received;
    const auto row = intervention_row(in);
    if (!intervention_repeats_.accept(in.request_id(), joined(row))) {
      ++intervention_counts_.duplicates;
      continue;
    }
    intervention_file_->write_row(row);
    if (history_) history_->add("interventions", csv_history_row(row));
    ++intervention_counts_.written;
    spdlog::info("intervention {} approved by {}: {} channel {} {:+.1f} % from snapshot {} for {}", in.request_id(),
                 in.approved_by(), in.asset_group(), in.channel(), in.change_percent(), in.start_snapshot_index(),
                 in.duration_snapshots());
  }
  for (const auto& [k, in] : outs) {
    ++outcome_counts_.received;
    const auto row = intervention_outcome_row(in);
    if (!outcome_repeats_.accept(in.request_id(), joined(row))) {
      ++outcome_counts_.duplicates;
      continue;
    }
    outcome_file_->write_row(row);
    if (history_) history_->add("intervention_outcomes", csv_history_row(row));
    ++outcome_counts_.written;
    spdlog::info("intervention outcome {}: {}", in.request_id(), in.text());
  }
  return ivs.size() + outs.size();
}

void InterventionTables::flush() {
  intervention_file_->flush();
  outcome_file_->flush();
}

}  // namespace causal::recorder
