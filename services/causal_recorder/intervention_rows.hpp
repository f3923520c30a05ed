// causal-recorder's part of the closed prescriptive loop: every approved intervention (causal_twin/intervention)
// to interventions.csv and every checked outcome (causal_twin/intervention_outcome) to intervention_outcomes.csv,
// each exactly once per request id (a transient-local replay of the same message is a duplicate). Rows are in
// publication order (writer, sequence number), so repeated runs give the same files.
#pragma once

#include "record_rows.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/io/csv_format.hpp"
#include "causal_twinPubSubTypes.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace causal::recorder {

inline constexpr const char* kInterventionsFile = "interventions.csv";
inline constexpr const char* kInterventionOutcomesFile = "intervention_outcomes.csv";

// Every field of Intervention / InterventionOutcome, in IDL order (times also as UTC).
const std::vector<std::string>& intervention_header();
std::vector<std::string> intervention_row(const causal_twin::Intervention& in);
const std::vector<std::string>& intervention_outcome_header();
std::vector<std::string> intervention_outcome_row(const causal_twin::InterventionOutcome& in);

class InterventionTables {
 public:
  // Opens (or appends to) both files in `out_dir`; the readers wake `loop`.
  InterventionTables(dds::Participant& participant, const std::filesystem::path& out_dir, dds::EventLoop& loop);
  // Takes what arrived and writes it; returns the number of messages taken (CSV only: the historian's database
  // has no intervention tables yet).
  std::size_t take();
  void flush();
  std::size_t matched_writers() const { return interventions_.matched_writers() + outcomes_.matched_writers(); }
  const TopicCounts& intervention_counts() const { return intervention_counts_; }
  const TopicCounts& outcome_counts() const { return outcome_counts_; }

 private:

  dds::TypedReader<causal_twin::InterventionPubSubType> interventions_;
  dds::TypedReader<causal_twin::InterventionOutcomePubSubType> outcomes_;
  std::unique_ptr<report::CsvFile> intervention_file_, outcome_file_;
  RepeatFilter intervention_repeats_, outcome_repeats_;
  TopicCounts intervention_counts_, outcome_counts_;
};

}  // namespace causal::recorder
