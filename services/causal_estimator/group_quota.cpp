#include "group_quota.hpp"

namespace causal::estimator {

namespace {
constexpr std::size_t kRememberRefused = 65536;  // bounds the memory a flood of new names can take here
}

GroupQuota::Verdict GroupQuota::admit(const std::string& group, const std::string& writer) {
  if (groups_.count(group) > 0) return Verdict::Known;
  Verdict v = Verdict::Admitted;
  std::size_t& mine = per_writer_[writer];
  if (groups_.size() >= limits_.max_groups) {
    v = Verdict::OverTotal;
  } else if (mine >= limits_.max_groups_per_writer) {
    v = Verdict::OverWriter;
  }
  if (v != Verdict::Admitted) {
    ++refused_inputs_;
    if (refused_groups_.size() < kRememberRefused) refused_groups_.insert(group);
    return v;
  }
  ++mine;
  groups_.insert(group);
  return v;
}

std::size_t GroupQuota::groups_of(const std::string& writer) const {
  const auto it = per_writer_.find(writer);
  return it == per_writer_.end() ? 0 : it->second;
}

const char* GroupQuota::to_string(Verdict v) {
  switch (v) {
    case Verdict::Known: return "known";
    case Verdict::Admitted: return "admitted";
    case Verdict::OverTotal: return "over_total";
    case Verdict::OverWriter: return "over_writer";
  }
  return "?";
}

}  // namespace causal::estimator
