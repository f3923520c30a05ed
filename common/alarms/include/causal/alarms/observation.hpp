// One observation of one asset group, as the alarm engine consumes it.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace causal::alarms {

// One snapshot (condition level) or one factor publication (sample level) of one asset group of G
// channels with F causal factors. Every vector is optional (size 0 = not available); when present it
// must have the stated size. Individual NaN entries mean "no value for this channel now".
struct Observation {
  std::uint64_t index = 0;  // snapshot index (condition level) or publication / sample index
  std::int64_t time_ns = 0; // UTC, ns since the Unix epoch
  // The observation does not continue the previous one (a gap in the recording, a restart of the source:
  // ConditionVector.discontinuity). The engine also finds gaps itself from time_ns (AlarmParams::gap_multiple).
  bool discontinuity = false;

  // G condition features (e.g. RMS or mean |x| per channel). Positive scale features are
  // log-transformed by the engine (AlarmParams::feature_log_transform).
  Eigen::VectorXd features;

  // G one-step innovations e_k = y_k - h_k^T x of the causal filter and their variances S_k.
  // e_k / sqrt(S_k) is the part of channel k that the other channels (through the causal factors)
  // do NOT explain: the engine's measure of a channel's "own" behaviour.
  Eigen::VectorXd innovations;
  Eigen::VectorXd innovation_variances;

  // Optional G mean normalised innovation squared over the samples this observation summarises
  // (sample-level publications carry nis_mean over thousands of samples; see OutcomeFactors in the IDL).
  // When present (finite) for channel k it replaces e_k^2 / S_k as channel k's unexplained-energy signal.
  Eigen::VectorXd mean_nis;

  // F causal factors (outcome-major, names given to the engine) and their standard deviations.
  Eigen::VectorXd factors;
  Eigen::VectorXd factor_std;
};

}  // namespace causal::alarms
