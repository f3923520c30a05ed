// Assembles the G per-outcome CausalFactors messages of one sample index into one CSV row:
//   index,time_ns,time_utc,<factor names of outcome 1..G>,<sd_ + each name>,<nis_ + outcome name ...>
// A row is ready once all G outcomes of its index arrived; at exit (or when too many rows are pending
// because an outcome never comes) pending rows are written partially, with empty cells.
#pragma once

#include "causal/dds/factor_conversions.hpp"

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace causal::recorder {

class FactorRowAssembler {
 public:
  enum class AddStatus {
    Stored,     // kept, its row still waits for other outcomes
    Completed,  // its row is complete and ready in take_rows()
    Refused     // inconsistent message (see counters().refused), nothing kept
  };

  struct Counters {
    std::uint64_t messages = 0;        // accepted messages
    std::uint64_t refused = 0;         // bad outcome / channel count / vector lengths
    std::uint64_t duplicates = 0;      // same (index, outcome) again while its row was pending: replaced
    std::uint64_t rows_complete = 0;
    std::uint64_t rows_partial = 0;    // written with empty cells (exit or overflow)
    std::uint64_t dropped_factors = 0; // factor values whose name has no column in the header
  };

  // max_pending bounds memory when an outcome stops arriving: the oldest pending row is then written
  // partially.
  explicit FactorRowAssembler(std::size_t max_pending = 1024);

  // m.outcome is 0-based (as from_causal_factors() returns it).
  AddStatus add(const dds::FactorMessage& m);

  // Rows ready to be written, oldest first; each has header().size() cells. Clears the queue.
  std::vector<std::vector<std::string>> take_rows();

  // Moves every pending row (complete or not) to the ready queue, by index. Call at exit.
  void flush_pending();

  // The header is fixed once every outcome was seen (or at the first forced partial row).
  bool has_header() const { return header_fixed_; }
  const std::vector<std::string>& header() const { return header_; }
  const Counters& counters() const { return counters_; }
  std::size_t pending() const { return pending_.size(); }
  int channel_count() const { return g_; }

 private:
  struct Part {
    bool present = false;
    std::vector<double> values, sds;
    double nis = 0.0;
    std::vector<std::string> names;  // only when they differ from the outcome's first names
  };
  struct Pending {
    std::int64_t time_ns = 0;
    std::vector<Part> parts;  // G
    int present = 0;
  };

  void fix_header();
  std::vector<std::string> format(std::uint64_t index, const Pending& p);
  void emit(std::map<std::uint64_t, Pending>::iterator it, bool complete);

  std::size_t max_pending_;
  int g_ = 0;  // channel count, from the first accepted message
  std::vector<std::vector<std::string>> names_;  // factor names per outcome (first seen)
  std::vector<std::string> outcome_names_;
  std::vector<bool> seen_;
  int seen_count_ = 0;
  bool header_fixed_ = false;
  std::vector<std::string> header_;
  std::vector<std::size_t> offset_;  // first value column of outcome k, relative to the factor block
  std::vector<std::unordered_map<std::string, std::size_t>> position_;  // name -> offset within outcome k
  std::size_t factor_total_ = 0;
  std::map<std::uint64_t, Pending> pending_;
  std::vector<std::vector<std::string>> ready_;
  Counters counters_;
};

}  // namespace causal::recorder
