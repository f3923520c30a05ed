// Reassembles what the alarm engine needs from the estimator's CausalFactorBatch messages, fed as one
// FactorMessage per outcome block: the G outcomes of one sample index (collected by dds::FactorSetAssembler,
// which also copes with a batch that lacks outcomes, or outcomes that arrive separately) become one Observation
// (innovations, NIS, all factors), joined with the asset group's condition vector of the same time at
// condition level. observation.index is the messages' sample_index (the snapshot index at condition level).
#pragma once

#include "causal/advice/alarm_desk.hpp"
#include "causal/alarms/observation.hpp"
#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/factor_set_assembler.hpp"

#include <Eigen/Core>

#include <deque>
#include <map>
#include <string>
#include <vector>

namespace causal::recommender {

// The alarm desk's plain input (advice::JudgedInput: asset group, channel and factor names, lag order, the engine's
// observation, the per-outcome covariance blocks P_k from the messages, the time scale): what the messages assemble.
using AssembledObservation = advice::JudgedInput;

class ObservationAssembler {
 public:
  // max_pending: complete observations held back waiting for their condition vector before they are
  // released without features (the two topics are not ordered with respect to each other).
  // max_pending_sets: factor sets per stream in assembly (FactorSetAssembler, Drop policy): a set still
  // missing an outcome when that many sets are pending is given up (the alarm engine needs all G
  // outcomes), so a lost message delays the observations behind it by at most that many sets.
  // Defaults: 64 each. Reliable delivery is in order per writer, but a reader that has no room for one
  // instance refuses its samples and gets them again later while the other instances flow on, so outcomes
  // (and the two topics) can be apart by a writer's and a reader's per-instance history (16 + 16 here).
  explicit ObservationAssembler(std::size_t max_pending = 64, std::size_t max_pending_sets = 64)
      : max_pending_(max_pending), sets_(max_pending_sets, dds::FactorSetAssembler::IncompletePolicy::Drop) {}

  // Filter estimates only (the alarm engine runs in real time); other kinds are ignored. Each index of a
  // stream becomes at most one observation, in index order (re-sent or replayed indices are duplicates,
  // see factor_counters()).
  void add_factors(const dds::FactorMessage& m, std::vector<AssembledObservation>& out);
  // discontinuity: ConditionVector.discontinuity (a gap in the run, a restart), passed on to the alarm engine.
  void add_condition(const std::string& asset_group, const std::string& feature, std::int64_t time_ns,
                     const Eigen::VectorXd& values, bool discontinuity, std::vector<AssembledObservation>& out);
  void add_condition(const std::string& asset_group, const std::string& feature, std::int64_t time_ns,
                     const Eigen::VectorXd& values, std::vector<AssembledObservation>& out) {
    add_condition(asset_group, feature, time_ns, values, false, out);
  }
  // Releases everything still held (end of stream); factor sets still missing an outcome are dropped.
  void flush(std::vector<AssembledObservation>& out);
  std::uint64_t dropped_incomplete() const { return sets_.counters().dropped; }
  // Condition vectors dropped before any observation could be joined with them (more than the bound kept
  // waiting for their factors, observation_assembler.cpp): their observations reach the engine without features.
  std::uint64_t evicted_conditions() const { return evicted_conditions_; }
  dds::FactorSetCounters factor_counters() const { return sets_.counters(); }
  const std::string& last_problem() const { return sets_.last_problem(); }  // why the last refusal

 private:
  using WaitingKey = std::pair<std::string, std::string>;  // asset group, feature
  void observe(const dds::FactorSet& set, std::vector<AssembledObservation>& out);
  void release(const WaitingKey& key, std::deque<AssembledObservation>& waiting, std::vector<AssembledObservation>& out,
               bool all);

  std::size_t max_pending_;
  dds::FactorSetAssembler sets_;
  // Condition-level observations waiting for their condition vector, by asset group + feature.
  std::map<WaitingKey, std::deque<AssembledObservation>> waiting_;
  // Condition vectors by asset group + feature, then time.
  struct Condition {
    Eigen::VectorXd values;
    bool discontinuity = false;
  };
  std::map<WaitingKey, std::map<std::int64_t, Condition>> features_;
  std::vector<dds::FactorSet> sets_ready_;  // scratch
  std::uint64_t evicted_conditions_ = 0;
};

}  // namespace causal::recommender
