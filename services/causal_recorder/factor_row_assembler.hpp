// Turns the factor sets of one recorded stream into CSV rows:
//   index,time_ns,time_utc,<factor names of outcome 1..G>,<sd_ + each name>,<nis_ + outcome name ...>
// The G per-outcome messages of one index are collected by dds::FactorSetAssembler (ReleasePartial
// policy): a row is ready once all G outcomes of its index arrived and every older row is out; each index
// is written at most once (re-sent or replayed indices are counted as duplicates); at exit (or when too
// many rows are pending because an outcome never comes) pending rows are written partially, with empty
// cells.
#pragma once

#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/factor_set_assembler.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace causal::recorder {

class FactorRowAssembler {
 public:
  enum class AddStatus {
    Stored,     // kept, no row ready yet (its row waits for other outcomes or an older row)
    Completed,  // kept, and rows are ready in take_rows()
    Duplicate,  // its index was already written, or its (index, outcome) is pending: dropped
    Refused     // inconsistent message (see counters().refused, last_problem()), nothing kept
  };

  struct Counters {
    std::uint64_t messages = 0;        // accepted messages
    std::uint64_t refused = 0;         // bad outcome / channel count / vector lengths / non-finite values
    std::uint64_t duplicates = 0;      // index already written, or (index, outcome) already pending: dropped
    std::uint64_t rows_complete = 0;
    std::uint64_t rows_partial = 0;    // written with empty cells (exit or overflow)
    std::uint64_t dropped_factors = 0; // factor values whose name has no column in the header
  };

  // max_pending bounds memory when an outcome stops arriving: the oldest pending row is then written
  // partially.
  explicit FactorRowAssembler(std::size_t max_pending = 1024);

  // m.outcome is 0-based (as from_causal_factors() returns it).
  AddStatus add(const dds::FactorMessage& m);

  // Rows ready to be written, in index order; each has header().size() cells. Clears the queue.
  std::vector<std::vector<std::string>> take_rows();

  // Moves every pending row (complete or not) to the ready queue, by index. Call at exit.
  void flush_pending();

  // The header is fixed once every outcome was seen (or at the first forced partial row).
  bool has_header() const { return header_fixed_; }
  const std::vector<std::string>& header() const { return header_; }
  Counters counters() const;
  const std::string& last_problem() const { return problem_.empty() ? sets_.last_problem() : problem_; }
  std::size_t pending() const { return sets_.pending(); }
  int channel_count() const { return g_; }
  // Per stream: counters and the condition-level indices never written (see dds::FactorStreamReport).
  std::vector<dds::FactorStreamReport> streams() const { return sets_.streams(); }

 private:
  void fix_header();
  std::vector<std::string> format(const dds::FactorSet& set);
  void emit(const std::vector<dds::FactorSet>& sets);

  dds::FactorSetAssembler sets_;
  int g_ = 0;  // channel count, from the first accepted message
  std::vector<std::vector<std::string>> names_;  // factor names per outcome (first seen)
  std::vector<std::string> outcome_names_;
  std::vector<bool> seen_;
  bool header_fixed_ = false;
  std::vector<std::string> header_;
  std::vector<std::size_t> offset_;  // first value column of outcome k, relative to the factor block
  std::vector<std::unordered_map<std::string, std::size_t>> position_;  // name -> offset within outcome k
  std::size_t factor_total_ = 0;
  std::vector<std::vector<std::string>> ready_;
  std::uint64_t refused_here_ = 0, dropped_factors_ = 0;
  std::string problem_;
};

}  // namespace causal::recorder
