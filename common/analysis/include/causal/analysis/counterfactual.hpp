// Counterfactuals over a past window, Pearl's three steps on (S1) y[n] = A0 y[n] + sum_l A_l y[n-l] + e[n]:
//   abduction   e[n] = (I - A0) y[n] - sum_l A_l y[n-l]          for n in [from, to]           (C1)
//   action      equations of the held channels replaced by y_j[n] := c_j            (graph surgery)
//   prediction  (I - A0c) y*[n] = sum_l A_lc y*[n-l] + e_c[n],  e_c = e with held rows set to c_j  (C2)
// with y*[n] = y[n] (observed) for n < from. It is computed in the equivalent deviation form
// d = y* - y, where (C1) cancels: (I - A0c) d[n] = sum_l A_lc d[n-l] + f[n], f_j = c_j - y_j[n] on held
// rows, 0 elsewhere (C2'). With no holds d = 0 exactly, so the data are reproduced bit for bit for ANY
// model (re-simulating y* directly would amplify rounding when the model is unstable). The window needs
// M samples of history before `from` (from >= lag_order).
//
// Limits: the model is taken as exact (no parameter uncertainty here) and as the true structural model;
// see structural_model.hpp for when the per-outcome regressions are one.
#pragma once

#include "causal/analysis/analysis_status.hpp"
#include "causal/analysis/structural_model.hpp"

#include <Eigen/Core>
#include <string>
#include <vector>

namespace causal::analysis {

struct Hold {
  int channel = 0;     // 0-based
  double value = 0.0;  // y_channel[n] := value over the window
};

struct CounterfactualQuery {
  int from = 0;  // first sample of the window (0-based, inclusive), >= lag_order
  int to = 0;    // last sample (inclusive), < data rows
  std::vector<Hold> holds;
};

struct CounterfactualResult {
  AnalysisStatus status = AnalysisStatus::ok;
  std::string message;
  int from = 0;
  int to = 0;
  Eigen::MatrixXd observed;        // (to - from + 1) x G, the data in the window
  Eigen::MatrixXd counterfactual;  // same shape: what the channels would have been (NaN if status != ok)
  Eigen::MatrixXd noise;           // same shape: the abducted structural noise e[n] (C1)
  // Stability of the system that produced the counterfactual: the largest companion spectral radius of the
  // model with the held equations replaced, over the window (0 without holds; NaN if not identifiable).
  // The window is finite, so the answer exists either way, but >= 1 means the change grows over the window
  // instead of settling: read a long window's end with that in mind.
  double spectral_radius = 0.0;
};

// One model for the whole window. Throws std::invalid_argument for a window outside the data, from <
// lag_order, a bad/duplicate hold channel or a malformed model. Non-finite data in the window or its
// history -> non_finite_input; singular (I - A0c) -> not_identifiable.
CounterfactualResult counterfactual(const StructuralModel& model, const Eigen::MatrixXd& data,
                                    const CounterfactualQuery& query);

// Time-varying factors: models[i] is the structural model at sample from + i (models.size() must equal
// to - from + 1), e.g. the filtered or smoothed estimates at each sample.
CounterfactualResult counterfactual(const std::vector<StructuralModel>& models, const Eigen::MatrixXd& data,
                                    const CounterfactualQuery& query);

}  // namespace causal::analysis
