// The recommendations alarm-recommender published, kept per asset group in
// DIR/<sanitised asset group>.recommendations.state (--state-dir), so a restarted recommender publishes them
// again: the recommendation topic keeps the last value per recommendation id for readers that join later
// (transient local), and without this a live view or recorder that joined after a restart saw the open alarms
// with none of their advice. Last value per recommendation id, as the topic keeps them. Written (atomically,
// not fsync'ed) after each recommendation is made, before it is published, like the alarm checkpoints.
#pragma once

#include "causal_twin.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace causal::recommender {

class RecommendationStore {
 public:
  explicit RecommendationStore(std::string state_dir);  // empty: nothing is kept (the directory exists already)

  // Remembers `r` (replacing the last one with its id) and writes its asset group's file. A failed write is
  // counted and logged, never thrown: advice keeps flowing when the disk is full.
  void record(const causal_twin::Recommendation& r);
  // Every recommendation of every file in the directory, for republishing at start. Throws causal::StateError
  // naming the file when one cannot be used.
  std::vector<causal_twin::Recommendation> load_all();

  std::uint64_t save_failures() const { return save_failures_; }

 private:
  std::string path(const std::string& asset_group) const;
  void save(const std::string& asset_group);

  std::string dir_;
  std::map<std::string, std::map<std::string, std::string>> kept_;  // group -> id -> message (CDR bytes)
  std::uint64_t save_failures_ = 0;
};

}  // namespace causal::recommender
