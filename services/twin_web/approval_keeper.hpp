// twin-web keeps the closed loop's approvals on the bus for as long as it runs: one RELIABLE, TRANSIENT_LOCAL,
// KEEP_LAST-per-request-id writer on causal_twin/intervention (profile intervention_writer, at most 4096 kept), so
// a reader that joins after the approval (a plant actuator that was down, a recorder or recommender restarted)
// still receives it. It holds
//  * the page's approvals (the approve button, through ApprovalBridge): at most one per recommendation;
//  * every approval another writer published (causal-approve, which leaves once its readers acknowledged), written
//    again unchanged: readers keep one approval per request id, so a reader that had it already ignores the copy.
//    A copy is made only when the original writer's grant names the approval's asset group (the readers' own
//    check, dds/writer_grant_check.hpp) and twin-web's grant names it too: twin-web never lends its grant.
// DDS thread only (the web threads reach it through the bridge).
#pragma once

#include "approval_request.hpp"

#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/dds/writer_grant_check.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace causal::web {

class ApprovalKeeper {
 public:
  explicit ApprovalKeeper(dds::Participant& participant);

  ApprovalBridge& bridge() { return bridge_; }
  // An approval read from the bus (any writer, twin-web's own too): queued to be kept when it is another's.
  // False when its writer is not entitled to the group: the plant and the recommender refuse it, so the page
  // must not show it as approved either.
  bool on_read(const causal_twin::Intervention& in, const eprosima::fastrtps::rtps::GUID_t& writer);
  // Writes the page's approvals that are due (answering the bridge) and the queued copies.
  void send_due(const std::atomic<bool>& stop);
  void stop() { bridge_.stop(); }
  void log_summary() const;

  struct Counts {
    std::uint64_t approved = 0;      // the page's approvals written
    std::uint64_t refused = 0;       // the page's approvals refused (already approved, not granted, write failed)
    std::uint64_t kept = 0;          // other writers' approvals written again
    std::uint64_t not_entitled = 0;  // other writers' approvals not kept: the writer's grant does not name the group
    std::uint64_t not_granted = 0;   // not kept: twin-web's own grant does not name the group
    std::uint64_t failed = 0;        // copies whose write failed
  };
  const Counts& counts() const { return counts_; }

 private:
  // Writes `iv` once per request id; the reason when it is not written.
  std::string keep(causal_twin::Intervention& iv, const std::atomic<bool>& stop);
  ApprovalResult approve(causal_twin::Intervention& iv, const std::atomic<bool>& stop);

  dds::TypedWriter<causal_twin::InterventionPubSubType> writer_;
  dds::WriterGrantCheck grants_;
  ApprovalBridge bridge_;
  std::vector<std::string> own_partitions_;
  std::set<std::string> written_;                     // request ids on the writer
  std::map<std::string, std::string> by_recommendation_;  // "<group>\n<recommendation id>" -> request id
  std::vector<causal_twin::Intervention> copies_;     // other writers' approvals to write
  Counts counts_;
};

}  // namespace causal::web
