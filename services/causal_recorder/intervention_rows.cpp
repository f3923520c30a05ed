#include "intervention_rows.hpp"

#include "row_cells.hpp"

#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <sstream>

namespace causal::recorder {

InterventionTables::InterventionTables(dds::Participant& participant, const std::filesystem::path& out_dir,
                                       dds::EventLoop& loop, HistorySink* history)
    : interventions_(participant, dds::topics::kIntervention, dds::profiles::kInterventionReader),
      outcomes_(participant, dds::topics::kInterventionOutcome, dds::profiles::kInterventionOutcomeReader),
      intervention_file_(
          std::make_unique<io::CsvFile>(out_dir / kInterventionsFile, header_of<causal_twin::Intervention>())),
      outcome_file_(std::make_unique<io::CsvFile>(out_dir / kInterventionOutcomesFile,
                                                  header_of<causal_twin::InterventionOutcome>())),
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
    const auto row = row_of(in);
    if (!intervention_counts_.admit(intervention_repeats_.accept(in.request_id(), row_signature(row)))) continue;
    write_row(*intervention_file_, history_, "interventions", row, intervention_counts_);
    spdlog::info("intervention {} approved by {}: {} channel {} {:+.1f} % from snapshot {} for {}", in.request_id(),
                 in.approved_by(), in.asset_group(), in.channel(), in.change_percent(), in.start_snapshot_index(),
                 in.duration_snapshots());
  }
  for (const auto& [k, in] : outs) {
    const auto row = row_of(in);
    if (!outcome_counts_.admit(outcome_repeats_.accept(in.request_id(), row_signature(row)))) continue;
    write_row(*outcome_file_, history_, "intervention_outcomes", row, outcome_counts_);
    spdlog::info("intervention outcome {}: {}", in.request_id(), in.text());
  }
  return ivs.size() + outs.size();
}

void InterventionTables::flush() {
  intervention_file_->flush();
  outcome_file_->flush();
}

}  // namespace causal::recorder
