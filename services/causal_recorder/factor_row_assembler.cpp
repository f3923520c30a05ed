#include "factor_row_assembler.hpp"

#include "csv_format.hpp"

#include "causal/io/time_format.hpp"

namespace causal::recorder {

using report::format_integer;
using report::format_number;

FactorRowAssembler::FactorRowAssembler(std::size_t max_pending) : max_pending_(max_pending < 1 ? 1 : max_pending) {}

FactorRowAssembler::AddStatus FactorRowAssembler::add(const dds::FactorMessage& m) {
  const auto n = static_cast<std::size_t>(m.factors.size());
  const bool shape_ok = m.channel_count >= 1 && m.outcome >= 0 && m.outcome < m.channel_count &&
                        m.factor_names.size() == n && static_cast<std::size_t>(m.factor_std.size()) == n;
  if (!shape_ok || (g_ != 0 && m.channel_count != g_)) {
    ++counters_.refused;
    return AddStatus::Refused;
  }
  if (g_ == 0) {
    g_ = m.channel_count;
    names_.assign(static_cast<std::size_t>(g_), {});
    outcome_names_.assign(static_cast<std::size_t>(g_), {});
    seen_.assign(static_cast<std::size_t>(g_), false);
  }
  const auto k = static_cast<std::size_t>(m.outcome);
  if (!seen_[k]) {
    seen_[k] = true;
    ++seen_count_;
    names_[k] = m.factor_names;
    outcome_names_[k] = m.outcome_name;
  }
  ++counters_.messages;

  auto it = pending_.find(m.sample_index);
  if (it == pending_.end()) {
    it = pending_.emplace(m.sample_index, Pending{}).first;
    it->second.time_ns = m.time_ns;
    it->second.parts.resize(static_cast<std::size_t>(g_));
  }
  Part& part = it->second.parts[k];
  if (part.present) {
    ++counters_.duplicates;
  } else {
    part.present = true;
    ++it->second.present;
  }
  part.values.assign(m.factors.data(), m.factors.data() + n);
  part.sds.assign(m.factor_std.data(), m.factor_std.data() + n);
  part.nis = m.nis_mean;
  if (m.factor_names != names_[k]) {
    part.names = m.factor_names;
  } else {
    part.names.clear();
  }

  if (it->second.present == g_) {
    if (!header_fixed_) fix_header();
    emit(it, true);
    return AddStatus::Completed;
  }
  // An outcome that never arrives must not grow memory without bound: write the oldest row partially.
  while (pending_.size() > max_pending_) {
    if (!header_fixed_) fix_header();
    emit(pending_.begin(), false);
  }
  return AddStatus::Stored;
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

std::vector<std::string> FactorRowAssembler::format(std::uint64_t index, const Pending& p) {
  std::vector<std::string> cells(header_.size());
  cells[0] = format_integer(index);
  cells[1] = format_integer(p.time_ns);
  cells[2] = io::format_utc(p.time_ns);
  const std::size_t values_at = 3, sds_at = 3 + factor_total_, nis_at = 3 + 2 * factor_total_;
  for (std::size_t k = 0; k < p.parts.size(); ++k) {
    const Part& part = p.parts[k];
    if (!part.present) continue;
    cells[nis_at + k] = format_number(part.nis);
    for (std::size_t i = 0; i < part.values.size(); ++i) {
      std::size_t pos = 0;
      if (part.names.empty()) {
        if (i >= names_[k].size() || !seen_[k] || position_[k].empty()) {
          ++counters_.dropped_factors;
          continue;
        }
        pos = i;
      } else {
        // The layout changed under the same outcome: place values by name, drop unknown names.
        const auto found = position_[k].find(part.names[i]);
        if (found == position_[k].end()) {
          ++counters_.dropped_factors;
          continue;
        }
        pos = found->second;
      }
      cells[values_at + offset_[k] + pos] = format_number(part.values[i]);
      cells[sds_at + offset_[k] + pos] = format_number(part.sds[i]);
    }
  }
  return cells;
}

void FactorRowAssembler::emit(std::map<std::uint64_t, Pending>::iterator it, bool complete) {
  ready_.push_back(format(it->first, it->second));
  ++(complete ? counters_.rows_complete : counters_.rows_partial);
  pending_.erase(it);
}

std::vector<std::vector<std::string>> FactorRowAssembler::take_rows() {
  std::vector<std::vector<std::string>> out;
  out.swap(ready_);
  return out;
}

void FactorRowAssembler::flush_pending() {
  if (pending_.empty()) return;
  if (!header_fixed_) fix_header();
  while (!pending_.empty()) emit(pending_.begin(), pending_.begin()->second.present == g_);
}

}  // namespace causal::recorder
