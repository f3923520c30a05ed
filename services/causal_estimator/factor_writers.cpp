// causal-estimator: the factor writers of the form in use (factor_writers.hpp).
#include "factor_writers.hpp"

#include "causal/dds/factor_sets.hpp"
#include "causal/dds/topics.hpp"

namespace causal::estimator {

FactorWriters::FactorWriters(dds::Participant& participant, bool sets) : sets_(sets) {
  // The same profiles in both forms: a profile is per endpoint, not per topic.
  const char* profile[2] = {dds::profiles::kCausalFactorsSampleWriter, dds::profiles::kCausalFactorsWriter};
  for (int condition = 1; condition >= 0; --condition) {  // condition level first, as before
    if (sets_) {
      set_[condition] = std::make_unique<SetWriter>(participant, dds::topics::kCausalFactorSets, profile[condition]);
    } else {
      batch_[condition] = std::make_unique<BatchWriter>(participant, dds::topics::kCausalFactors, profile[condition]);
    }
  }
}

namespace {

causal_twin::CausalFactorSet set_of_one(const causal_twin::CausalFactorBatch& batch) {
  causal_twin::CausalFactorSet set;
  set.asset_group(batch.asset_group());
  set.time_scale(batch.time_scale());
  set.version(dds::kFactorSetVersion);
  set.batches().push_back(batch);
  return set;
}

}  // namespace

dds::WriteResult FactorWriters::write(bool condition, causal_twin::CausalFactorBatch& batch,
                                      const std::atomic<bool>& stop) {
  if (!sets_) return batch_[condition]->write(batch, stop);
  auto set = set_of_one(batch);
  return set_[condition]->write(set, stop);
}

dds::WriteResult FactorWriters::write(bool condition, causal_twin::CausalFactorSet& set, const std::atomic<bool>& stop) {
  if (sets_) return set_[condition]->write(set, stop);
  for (auto& batch : set.batches()) {
    const auto result = batch_[condition]->write(batch, stop);
    if (result != dds::WriteResult::Ok) return result;  // a retry writes the whole set again: readers drop by index
  }
  return dds::WriteResult::Ok;
}

bool FactorWriters::try_write(causal_twin::CausalFactorBatch& batch) {
  return batch_[0]->try_write(batch) == dds::WriteResult::Ok;
}

bool FactorWriters::try_write(causal_twin::CausalFactorSet& set) {
  return set_[0]->try_write(set) == dds::WriteResult::Ok;
}

std::string FactorWriters::wait_for_readers(const std::vector<dds::NamedReaders>& wanted,
                                            std::chrono::milliseconds timeout, const std::atomic<bool>& stop) {
  for (int condition = 1; condition >= 0; --condition) {
    const std::string missing = sets_ ? dds::wait_for_named_readers(*set_[condition], wanted, timeout, stop)
                                      : dds::wait_for_named_readers(*batch_[condition], wanted, timeout, stop);
    if (!missing.empty()) return missing;
  }
  return "";
}

bool FactorWriters::condition_acknowledged(std::chrono::milliseconds wait) {
  return sets_ ? set_[1]->wait_for_acknowledgments(wait) : batch_[1]->wait_for_acknowledgments(wait);
}

bool FactorWriters::acknowledged(std::chrono::milliseconds wait) {
  const bool sample = sets_ ? set_[0]->wait_for_acknowledgments(wait) : batch_[0]->wait_for_acknowledgments(wait);
  return condition_acknowledged(wait) && sample;
}

}  // namespace causal::estimator
