// Admission of new asset groups into one causal-estimator: every asset group costs a
// pipeline (filters, smoothers, calibration buffers: about 80 kB for 4 channels) and a checkpoint file, and any
// writer on the domain can name new groups. Without a bound, one faulty or hostile writer that numbers its group
// ids (seen: 1,023 groups from one writer, RSS 50 -> 133 MB, 1,032 checkpoint files) exhausts the host.
// Two bounds, both configurable (causal-estimator --max-groups, --max-groups-per-writer):
//  * total: asset groups this estimator serves (default 1024, what deploy/dds/qos.xml's readers are sized for);
//  * per writer: new asset groups one writer (a DDS writer: one source process) may open (default 256, the
//    largest single source the tests run: sensor-sim --groups 256).
// A group already admitted is always served, whoever writes it. DDS-free (writers are named by a string).
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>

namespace causal::estimator {

struct GroupQuotaLimits {
  std::size_t max_groups = 1024;
  std::size_t max_groups_per_writer = 256;
};

class GroupQuota {
 public:
  enum class Verdict { Known, Admitted, OverTotal, OverWriter };
  explicit GroupQuota(GroupQuotaLimits limits) : limits_(limits) {}
  // Decides about input of `group` from `writer`; Admitted the first time a group is accepted (it counts from
  // then on). Refusals are counted per group (refused_inputs) and the refused groups remembered (bounded).
  Verdict admit(const std::string& group, const std::string& writer);
  // A group that exists without being admitted here (restored from a checkpoint at start): counts to the total.
  void add_existing(const std::string& group) { groups_.insert(group); }
  std::size_t groups() const { return groups_.size(); }
  std::uint64_t refused_inputs() const { return refused_inputs_; }
  std::size_t refused_groups() const { return refused_groups_.size(); }
  const GroupQuotaLimits& limits() const { return limits_; }
  std::size_t groups_of(const std::string& writer) const;
  static const char* to_string(Verdict v);

 private:
  GroupQuotaLimits limits_;
  std::set<std::string> groups_;
  std::map<std::string, std::size_t> per_writer_;
  std::set<std::string> refused_groups_;  // at most kRememberRefused names (their count is what matters)
  std::uint64_t refused_inputs_ = 0;
};

}  // namespace causal::estimator
