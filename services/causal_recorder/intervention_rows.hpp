// causal-recorder's part of the closed prescriptive loop: every approved intervention (causal_twin/intervention)
// to interventions.csv and every checked outcome (causal_twin/intervention_outcome) to intervention_outcomes.csv,
// each exactly once per request id (a transient-local replay of the same message is a duplicate). Rows are in
// publication order (writer, sequence number), so repeated runs give the same files. With --db the same rows go to
// the historian's tables interventions and intervention_outcomes (keyed by asset group and request id).
// An approval is recorded only when its writer's grant, as of the writer's first discovery, names its asset group
// (dds/writer_grant_check.hpp, the check of the plant and alarm-recommender): the others were never approved for
// that group, so they are refused (counted in the topic's refused, logged with a HEALTH line naming the writer's
// participant; the recorder's identity publishes nothing) and make the exit code 4.
#pragma once

#include "history_sink.hpp"
#include "record_rows.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/dds/writer_grant_check.hpp"
#include "causal/io/csv_format.hpp"
#include "causal_twinPubSubTypes.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace causal::recorder {

inline constexpr const char* kInterventionsFile = "interventions.csv";
inline constexpr const char* kInterventionOutcomesFile = "intervention_outcomes.csv";

// Their columns: every field of Intervention / InterventionOutcome, in IDL order, times also as UTC
// (header_of / row_of, row_cells.hpp).

class InterventionTables {
 public:
  // Opens (or appends to) both files in `out_dir`; the readers wake `loop`. `history` (may be null: no --db)
  // receives the same rows; its owner commits them.
  InterventionTables(dds::Participant& participant, const std::filesystem::path& out_dir, dds::EventLoop& loop,
                     HistorySink* history);
  // Takes what arrived and writes it (files and history); returns the number of messages taken.
  std::size_t take();
  void flush();
  // The publishers the recorder's idle exit waits for: the outcomes' (alarm-recommender). Approval writers are not
  // counted: twin-web keeps its approval writer for its whole run (approvals for late readers), which would keep
  // an idle-exiting recorder from ever finishing beside a live view.
  std::size_t matched_writers() const { return outcomes_.matched_writers(); }
  const TopicCounts& intervention_counts() const { return intervention_counts_; }
  const TopicCounts& outcome_counts() const { return outcome_counts_; }

 private:
  dds::TypedReader<causal_twin::InterventionPubSubType> interventions_;
  dds::TypedReader<causal_twin::InterventionOutcomePubSubType> outcomes_;
  std::unique_ptr<io::CsvFile> intervention_file_, outcome_file_;
  HistorySink* history_ = nullptr;
  dds::WriterGrantCheck grants_;
  RepeatFilter intervention_repeats_, outcome_repeats_;
  TopicCounts intervention_counts_, outcome_counts_;
};

}  // namespace causal::recorder
