// causal-estimator: the checkpoint's resend list. Every condition-level message stays in it until the readers
// acknowledged it (unacked_output.hpp); a restarted estimator sends the list again (consumers drop by index).
#include "estimator_publishing.hpp"
#include "wire_bytes.hpp"

#include <spdlog/spdlog.h>

namespace causal::estimator {

bool EstimatorPublisher::restore(const std::string& name, GroupState& a) {
  std::vector<std::string> resend;
  if (!store_.restore(name, a.pipeline, resend, &a.last_time_ns)) return false;
  // The names come with the checkpoint: output (finish() at exit included) needs them before any new input.
  a.channel_names = a.pipeline.channel_names();
  resend_restored(name, a, resend);
  return true;
}

void EstimatorPublisher::resend_restored(const std::string& name, GroupState& a, const std::vector<std::string>& resend) {
  // Listed again until acknowledged: a second kill before the readers have them must not lose them.
  a.unacked.begin_snapshot();
  std::size_t sent = 0;
  for (const auto& bytes : resend) {
    if (bytes.empty()) continue;
    const std::string body = bytes.substr(1);
    if (bytes[0] == 'C') {
      auto msg = std::make_shared<causal_twin::ConditionVector>();
      if (!from_bytes<causal_twin::ConditionVectorPubSubType>(body, *msg)) continue;
      auto flag = a.unacked.add(bytes);
      outbound_.push("condition_vector", dds::OutboundQueue::Class::Essential,
                     [this, msg, flag](const std::atomic<bool>& s) { return mark(conditions_out_.write(*msg, s), flag); },
                     stop_);
    } else if (bytes[0] == 'B') {  // 'F' (one message per outcome) was the form before batches: not restored
      if (!resend_factors<causal_twin::CausalFactorBatchPubSubType>(a, bytes)) continue;
    } else if (bytes[0] == 'S') {  // output.factor_messages set; sent in the form in use now (FactorWriters)
      if (!resend_factors<causal_twin::CausalFactorSetPubSubType>(a, bytes)) continue;
    } else {
      continue;
    }
    ++sent;
  }
  if (sent > 0) {
    spdlog::info("asset '{}': {} condition-level output messages the readers had not acknowledged when the checkpoint "
                 "was written sent again (readers that have them drop them by index)", name, sent);
  }
}

template <typename PubSubType>
bool EstimatorPublisher::resend_factors(GroupState& a, const std::string& bytes) {
  auto msg = std::make_shared<typename PubSubType::type>();
  if (!from_bytes<PubSubType>(bytes.substr(1), *msg)) return false;
  auto flag = a.unacked.add(bytes);
  outbound_.push(factors_.sets() ? "causal_factor_sets/condition" : "causal_factors/condition",
                 dds::OutboundQueue::Class::Essential,
                 [this, msg, flag](const std::atomic<bool>& s) { return mark(factors_.write(true, *msg, s), flag); },
                 stop_);
  return true;
}

dds::WriteResult EstimatorPublisher::mark(dds::WriteResult result, const UnackedOutput::Flag& flag) {
  if (result == dds::WriteResult::Ok && flag) flag->store(true);
  return result;
}

void EstimatorPublisher::settle_unacked(GroupState& a, bool begin_snapshot) {
  const std::uint64_t dropped = a.unacked.dropped();
  a.unacked.settle([this] {
    return conditions_out_.wait_for_acknowledgments(std::chrono::milliseconds(0)) &&
           factors_.condition_acknowledged(std::chrono::milliseconds(0));
  });
  if (begin_snapshot) a.unacked.begin_snapshot();  // the oldest snapshot leaves here when the list is full
  if (a.unacked.dropped() > dropped) {
    // Said once at warning level, then at debug: while a reader is stuck this would repeat at every snapshot.
    spdlog::log(dropped == 0 ? spdlog::level::warn : spdlog::level::debug, "the readers have not acknowledged the output of the last {} snapshots: {} older messages are no "
                 "longer kept in the checkpoint (still queued; a crash now would lose them, the readers count them)",
                 UnackedOutput::kMaxSnapshots, a.unacked.dropped());
  }
}

}  // namespace causal::estimator
