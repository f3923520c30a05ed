#include "factor_row_assembler.hpp"

#include "causal/io/csv_format.hpp"

#include "causal/io/time_format.hpp"

#include <algorithm>

namespace causal::recorder {

using io::format_integer;
using io::format_number;

FactorRowAssembler::FactorRowAssembler(std::size_t max_pending)
    : sets_(max_pending < 1 ? 1 : max_pending, dds::FactorSetAssembler::IncompletePolicy::ReleasePartial) {}

FactorRowAssembler::AddStatus FactorRowAssembler::add(const dds::FactorMessage& m) {
  // One file has one column layout: a channel count other than the file's first is refused here, even
  // when it comes on another stream (another feature) of the same file.
  if (g_ != 0 && m.channel_count != g_) {
    ++refused_here_;
    problem_ = "channel count " + std::to_string(m.channel_count) + " differs from the file's " + std::to_string(g_);
    return AddStatus::Refused;
  }
  std::vector<dds::FactorSet> sets;
  switch (sets_.add(m, sets)) {
    case dds::FactorSetAssembler::AddStatus::Refused:
      problem_.clear();  // the assembler's reason is the latest
      return AddStatus::Refused;
    case dds::FactorSetAssembler::AddStatus::Duplicate: return AddStatus::Duplicate;
    case dds::FactorSetAssembler::AddStatus::Accepted: break;
  }
  if (g_ == 0) {
    g_ = m.channel_count;
    names_.assign(static_cast<std::size_t>(g_), {});
    outcome_names_.assign(static_cast<std::size_t>(g_), {});
    seen_.assign(static_cast<std::size_t>(g_), false);
  }
  // Names come from the first message of each outcome, so a header forced early (partial row) still
  // names every outcome seen so far, pending or not.
  const auto k = static_cast<std::size_t>(m.outcome);
  if (!seen_[k]) {
    seen_[k] = true;
    names_[k] = m.factor_names;
    outcome_names_[k] = m.outcome_name;
  }
  if (sets.empty()) return AddStatus::Stored;
  emit(sets);
  return AddStatus::Completed;
}

void FactorRowAssembler::emit(const std::vector<dds::FactorSet>& sets) {
  if (sets.empty()) return;
  if (!header_fixed_) fix_header();
  for (const auto& set : sets) ready_.push_back(format(set));
}

FactorRowAssembler::Counters FactorRowAssembler::counters() const {
  const dds::FactorSetCounters c = sets_.counters();
  Counters out;
  out.messages = c.accepted;
  out.refused = c.refused + refused_here_;
  out.duplicates = c.duplicates;
  out.rows_complete = c.complete;
  out.rows_partial = c.partial;
  out.dropped_factors = dropped_factors_;
  return out;
}

void FactorRowAssembler::fix_header() {
  header_fixed_ = true;
  header_ = {"index", "time_ns", "time_utc"};
  offset_.assign(static_cast<std::size_t>(g_), 0);
  position_.assign(static_cast<std::size_t>(g_), {});
  factor_total_ = 0;
  // Outcome-major factor block (the model's own order), then the same names with sd_, then one NIS per
  // outcome. An outcome never seen has no factor columns (its names are unknown), only its NIS column.
  for (std::size_t k = 0; k < static_cast<std::size_t>(g_); ++k) {
    offset_[k] = factor_total_;
    for (std::size_t i = 0; i < names_[k].size(); ++i) {
      header_.push_back(names_[k][i]);
      position_[k].emplace(names_[k][i], i);
    }
    factor_total_ += names_[k].size();
  }
  for (std::size_t k = 0; k < static_cast<std::size_t>(g_); ++k) {
    for (const auto& name : names_[k]) header_.push_back("sd_" + name);
  }
  for (std::size_t k = 0; k < static_cast<std::size_t>(g_); ++k) {
    const std::string name = outcome_names_[k].empty() ? "y" + std::to_string(k + 1) : outcome_names_[k];
    header_.push_back("nis_" + name);
  }
}

std::vector<std::string> FactorRowAssembler::format(const dds::FactorSet& set) {
  std::vector<std::string> cells(header_.size());
  cells[0] = format_integer(set.index);
  cells[1] = format_integer(set.time_ns);
  cells[2] = io::format_utc(set.time_ns);
  const std::size_t values_at = 3, sds_at = 3 + factor_total_, nis_at = 3 + 2 * factor_total_;
  for (std::size_t k = 0; k < set.present.size(); ++k) {
    if (!set.present[k]) continue;
    cells[nis_at + k] = format_number(set.outcomes[k].nis_mean);
    const auto first = static_cast<std::size_t>(set.factor_offset[k]);
    const auto count = static_cast<std::size_t>(set.factor_offset[k + 1]) - first;
    const bool same_layout =
        count == names_[k].size() &&
        std::equal(names_[k].begin(), names_[k].end(), set.factor_names.begin() + static_cast<std::ptrdiff_t>(first));
    for (std::size_t i = 0; i < count; ++i) {
      std::size_t pos = i;
      if (!same_layout || position_[k].empty()) {
        // The layout changed under the same outcome (or the outcome had no columns when the header was
        // fixed): place values by name, drop unknown names.
        const auto found = position_[k].find(set.factor_names[first + i]);
        if (found == position_[k].end()) {
          ++dropped_factors_;
          continue;
        }
        pos = found->second;
      }
      const auto at = static_cast<Eigen::Index>(first + i);
      cells[values_at + offset_[k] + pos] = format_number(set.factors[at]);
      cells[sds_at + offset_[k] + pos] = format_number(set.factor_std[at]);
    }
  }
  return cells;
}

std::vector<std::vector<std::string>> FactorRowAssembler::take_rows() {
  std::vector<std::vector<std::string>> out;
  out.swap(ready_);
  return out;
}

void FactorRowAssembler::flush_pending() {
  std::vector<dds::FactorSet> sets;
  sets_.flush(sets);
  emit(sets);
}

}  // namespace causal::recorder
