// causal-estimator: the factor writers of the form in use (estimator.yaml output.factor_messages). Per time
// scale one writer: of CausalFactorBatch on causal_twin/causal_factors (batch: one message per batch), or of
// CausalFactorSet on causal_twin/causal_factor_sets (set: one message per input, its batches in write order).
// The other form's writers are not created, so `--wait-for` and the acknowledgements concern the writers in use.
// Condition level and sample level have their own writers (qos.xml: the sample level's deeper ring, no blocking).
#pragma once

#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

namespace causal::estimator {

class FactorWriters {
 public:
  FactorWriters(dds::Participant& participant, bool sets);

  bool sets() const { return sets_; }
  // Writes one message of the form in use. A batch given to set writers goes as a set of one, a set given to
  // batch writers as its batches in order: a checkpoint's resend list written in the other form is sent too.
  dds::WriteResult write(bool condition, causal_twin::CausalFactorBatch& batch, const std::atomic<bool>& stop);
  dds::WriteResult write(bool condition, causal_twin::CausalFactorSet& set, const std::atomic<bool>& stop);
  // Sample level, one attempt (the writer never blocks): true when written.
  bool try_write(causal_twin::CausalFactorBatch& batch);
  bool try_write(causal_twin::CausalFactorSet& set);

  // "" when every named reader matched both writers within `timeout`; else the first one missing.
  std::string wait_for_readers(const std::vector<dds::NamedReaders>& wanted, std::chrono::milliseconds timeout,
                               const std::atomic<bool>& stop);
  // True when every matched reader acknowledged everything either writer wrote.
  bool acknowledged(std::chrono::milliseconds wait);
  // The condition-level one only (the checkpoint's resend list holds condition-level output).
  bool condition_acknowledged(std::chrono::milliseconds wait);

 private:
  using BatchWriter = dds::TypedWriter<causal_twin::CausalFactorBatchPubSubType>;
  using SetWriter = dds::TypedWriter<causal_twin::CausalFactorSetPubSubType>;
  bool sets_;
  std::unique_ptr<BatchWriter> batch_[2];  // [condition]
  std::unique_ptr<SetWriter> set_[2];      // [condition]
};

}  // namespace causal::estimator
