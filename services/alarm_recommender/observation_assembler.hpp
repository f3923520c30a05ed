// Reassembles what the alarm engine needs from the per-outcome CausalFactors messages of the estimator:
// the G messages of one sample index become one Observation (innovations, NIS, all factors), joined with
// the asset group's condition vector of the same time at condition level.
#pragma once

#include "causal/alarms/observation.hpp"
#include "causal/dds/factor_conversions.hpp"

#include <Eigen/Core>

#include <deque>
#include <map>
#include <string>
#include <vector>

namespace causal::recommender {

struct AssembledObservation {
  std::string asset_group;
  causal_twin::TimeScale time_scale = causal_twin::CONDITION_LEVEL;
  std::vector<std::string> channel_names;  // G, outcome order
  std::vector<std::string> factor_names;   // F, outcome-major
  int lag_order = 1;
  alarms::Observation observation;
  // Per outcome k (0-based), the full factor covariance P_k from the messages. Empty unless EVERY outcome
  // carried a valid block (factors.size() square), so a consumer either has all of them or none.
  std::vector<Eigen::MatrixXd> covariance_blocks;
};

class ObservationAssembler {
 public:
  // max_pending: complete observations held back waiting for their condition vector before they are
  // released without features (the two topics are not ordered with respect to each other).
  explicit ObservationAssembler(std::size_t max_pending = 4) : max_pending_(max_pending) {}

  // Filter estimates only (the alarm engine runs in real time); other kinds are ignored.
  void add_factors(const dds::FactorMessage& m, std::vector<AssembledObservation>& out);
  void add_condition(const std::string& asset_group, const std::string& feature, std::int64_t time_ns,
                     const Eigen::VectorXd& values, std::vector<AssembledObservation>& out);
  // Releases everything still held (end of stream).
  void flush(std::vector<AssembledObservation>& out);
  std::uint64_t dropped_incomplete() const { return dropped_incomplete_; }

 private:
  struct Partial {
    std::vector<dds::FactorMessage> outcomes;  // indexed by outcome
    int received = 0;
  };
  struct Stream {  // one asset group and time scale
    std::map<std::uint64_t, Partial> partial;
    std::deque<AssembledObservation> waiting_features;
    std::string feature;
  };
  void complete(Stream& s, Partial& p, std::vector<AssembledObservation>& out);
  void release(Stream& s, std::vector<AssembledObservation>& out, bool all);

  std::size_t max_pending_;
  std::map<std::pair<std::string, int>, Stream> streams_;
  // Condition vectors by asset group + feature, then time.
  std::map<std::pair<std::string, std::string>, std::map<std::int64_t, Eigen::VectorXd>> features_;
  std::uint64_t dropped_incomplete_ = 0;
};

}  // namespace causal::recommender
