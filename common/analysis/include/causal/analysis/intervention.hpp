// What-if: the predicted change of every channel under an intervention on channel j, by graph surgery
// on the structural model (S1) y[n] = A0 y[n] + sum_l A_l y[n-l] + e[n].
//
// d[n] = y_do[n] - y[n] is the change against the same noise realisation; for a linear model it does
// not depend on the noise, so it is exactly the interventional mean effect E[y | do] - E[y].
//
// Sustained shift, do(y_j[n] := y_j[n] + delta for all n >= n0): equation j is replaced (rows j of A0
// and A_l cut to zero, written A0c, A_lc); for n >= n0
//     (I - A0c) d[n] = sum_l A_lc d[n-l] + e_j delta                                        (W1)
//   immediate     d[n0] = (I - A0c)^{-1} e_j delta                                          (W2)
//   steady state  d_ss  = (I - A0c - sum_l A_lc)^{-1} e_j delta                              (W3)
// (W3) exists only when the intervened system is stable (companion spectral radius < 1).
//
// One-sample impulse, do(y_j[n0] := y_j[n0] + delta) at n0 only: (W2) at n0, then the ORIGINAL
// equations drive the change: (I - A0) d[n] = sum_l A_l d[n-l] for n > n0. Its steady state is 0 when
// the original system is stable; we also report the cumulative change sum_n d[n], from summing that
// recursion over n > n0:
//   cumulative    D = (I - A0 - sum_l A_l)^{-1} (I - A0) d[n0]                               (W4)
//
// Every solve is an LU solve (no explicit inverse). Singular (I - A0c) -> not_identifiable; unstable
// system -> unstable with the immediate change still filled in (it needs no stability).
#pragma once

#include "causal/analysis/analysis_status.hpp"
#include "causal/analysis/structural_model.hpp"

#include <Eigen/Core>
#include <string>

namespace causal::analysis {

enum class InterventionKind { impulse, sustained };

struct InterventionQuery {
  int channel = 0;  // 0-based j
  double delta = 0.0;
  InterventionKind kind = InterventionKind::sustained;
  int horizon = 0;  // if > 0, also return the change path d[n0 .. n0 + horizon - 1]
};

struct InterventionEffect {
  AnalysisStatus status = AnalysisStatus::ok;
  std::string message;
  Eigen::VectorXd immediate;     // G, (W2); NaN if not identifiable. Entry j is delta.
  Eigen::VectorXd steady_state;  // G: sustained (W3); impulse 0. NaN when status != ok.
  Eigen::VectorXd cumulative;    // G: impulse (W4); sustained: size 0 (the sum diverges). NaN when status != ok.
  Eigen::MatrixXd path;          // horizon x G change path (row 0 = immediate); NaN rows if not identifiable
  double spectral_radius = 0.0;  // of the system that decides the steady state (intervened for sustained,
                                 // original for impulse); NaN when not identifiable
};

// Throws std::invalid_argument for a bad channel, negative horizon or malformed model. Non-finite delta
// or model -> non_finite_input.
InterventionEffect predict_intervention(const StructuralModel& model, const InterventionQuery& query);

const char* to_string(InterventionKind kind);

}  // namespace causal::analysis
