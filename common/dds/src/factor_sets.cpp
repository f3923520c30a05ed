// The reader of causal_twin/causal_factor_sets (factor_sets.hpp).
#include "causal/dds/factor_sets.hpp"

#include <spdlog/spdlog.h>

#include <stdexcept>

namespace causal::dds {

std::unique_ptr<FactorSetReader> make_factor_set_reader(Participant& participant) {
  try {
    return std::make_unique<FactorSetReader>(participant, topics::kCausalFactorSets, profiles::kCausalFactorsReader);
  } catch (const std::invalid_argument& e) {  // DDS-Security refused it (TypedReader says so with this type)
    if (!participant.secured()) throw;
    spdlog::warn("{}: reading causal factors from {} only (issue this identity again with "
                 "deploy/security/issue-identity.sh to read an estimator that writes output.factor_messages: set)",
                 e.what(), topics::kCausalFactors);
    return nullptr;
  }
}

}  // namespace causal::dds
