// How far a learned VAR-LiNGAM causal order can be trusted, so lever claims are made only on an order the
// data actually identify. Two checks on the calibration window's VAR residuals u:
//  * non-Gaussianity: LiNGAM identifies j -> k only when at most one of the two disturbances is Gaussian.
//    Each structural disturbance e = (I - B0) u gets a Jarque-Bera test; a channel whose JB p-value is above
//    gaussian_p (Gaussianity not rejected) is "Gaussian-like". A linked pair of two Gaussian-like channels
//    has an arbitrary order: its stability is 0.
//  * bootstrap stability: DirectLiNGAM is re-run on `resamples` resamples (rows drawn with replacement) of
//    u; for every MATERIAL pair (standardised |B0| >= max(material_link, significance_z / sqrt(n))) the share of
//    resamples that keep its order. An order LiNGAM cannot see flips at random (share near 0.5).
// confidence = the smallest share over the material pairs (1 when there are none: nothing instantaneous to
// order); trusted = confidence >= min_confidence. Deterministic for a given seed. No resampling when a
// material pair is already unorderable (both Gaussian-like); wide groups get fewer resamples (cost G^3 n).
#pragma once

#include "causal/analysis/var_lingam.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace causal::analysis {

struct OrderTrustOptions {
  int resamples = 50;          // for up to 4 channels; fewer for wider groups (50 x 16 / G^2, at least 10)
  std::uint64_t seed = 20261127;
  double material_link = 0.1;  // standardised |B0(k, j)| sd(u_j) / sd(u_k) that makes a pair matter ...
  double significance_z = 3.0; // ... and at least this many standard errors (1/sqrt(n)) from zero
  double gaussian_p = 0.05;    // Jarque-Bera p-value above which a disturbance counts as Gaussian-like
  double min_confidence = 0.8; // trusted at or above
};

struct OrderTrust {
  double confidence = 0.0;            // in [0, 1]
  bool trusted = false;
  int material_pairs = 0;
  int gaussian_like = 0;              // channels whose disturbance looks Gaussian
  std::vector<double> jarque_bera_p;  // per channel
  int resamples_failed = 0;           // DirectLiNGAM refused a resample (counted, not used)
  std::string summary;                // one line for the log
};

// Jarque-Bera p-value (chi-square 2 dof: exp(-JB / 2)) of a sample; 1 for fewer than 8 values.
double jarque_bera_p(const Eigen::VectorXd& x);

// result: var_lingam() on the calibration window.
OrderTrust assess_order(const VarLingamResult& result, const OrderTrustOptions& options = {});

}  // namespace causal::analysis
