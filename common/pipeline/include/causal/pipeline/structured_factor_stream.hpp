// A FactorStream whose model structure is learned online, on a calibration window at the start of the stream.
//
// Two things a configured model cannot know in advance:
//  * the healthy operating point. The regressions (S1) have no intercept, so with un-centred inputs (e.g. log
//    vibration levels around -2.5) a channel with no causal link to k still gets a factor x_kj that carries
//    k's mean (y_j acts as a constant regressor). What-if answers on unlinked channels are then spurious.
//    Centring every input on the calibration-window mean (the healthy baseline) removes this: the factors
//    describe how deviations from healthy propagate. Interventions are shifts, so their predictions do not
//    need the centre; counterfactuals on levels add it back.
//  * the causal order of the instantaneous links. With both x_kj and x_jk free the per-outcome regressions
//    are not one identified structural model (causal_graph.hpp). For non-Gaussian noise VAR-LiNGAM
//    (Hyvärinen et al. 2010, analysis/var_lingam.hpp) identifies the order from the calibration window; the
//    filter then tracks time-varying factors restricted to it: j may cause k at once only if j precedes k.
//
// Nothing is lost: the window is buffered, the structure learned, the FactorStream built and the window
// replayed through it, so reports cover every sample from the first. If learning fails (too few usable
// samples, a constant channel, ...) the configured model runs and LearnedStructure::problem says why.
#pragma once

#include "causal/pipeline/factor_stream.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace causal::pipeline {

struct StructureSetting {
  std::size_t calibration_samples = 0;  // window length; 0: no structure learning (centre/learn_order false)
  bool centre = false;                  // subtract the window mean of every channel from every input
  bool learn_order = false;             // restrict the instantaneous links to the VAR-LiNGAM order
  double prune_threshold = 0.0;         // also drop learned links with |B0(k, j)| below this (0 keeps all)
};

struct LearnedStructure {
  bool ready = false;            // the model is built (after the window, or at once without learning)
  std::size_t samples = 0;       // samples in the calibration window
  Eigen::VectorXd centre;        // subtracted from every input; size 0 when inputs are not centred
  std::vector<int> order;        // learned causal order, causes first (0-based); empty when not learned
  Eigen::MatrixXd b0;            // learned instantaneous structural coefficients B0(k, j); empty when not learned
  // The instantaneous links j -> k the model runs with, [k][j]; empty = every link (nothing restricted).
  std::vector<std::vector<bool>> instantaneous_allowed;
  // The channel blocks the order is learned in (0-based, contiguous): one block of all G channels when the
  // window holds 10 x G x (M + 1) samples, else blocks of at most window / (10 x (M + 1)) channels with no
  // instantaneous link between blocks (src/block_order.hpp). Set at construction when learn_order; not
  // checkpointed (a function of G, M and the window, which are).
  std::vector<std::vector<int>> blocks;
  std::string problem;           // non-empty: (part of) the learning failed and the configured model runs
  // How far the instantaneous causal order the model runs with can be trusted (analysis/order_trust.hpp),
  // published on CausalFactorBatch: "configured" (the plant's graph), "learned" (VAR-LiNGAM, stable and
  // identifiable), "untrusted" (learned, but unstable over bootstrap resamples or too Gaussian), "" (neither:
  // every instantaneous link free). Assessed on the calibration window; the model itself is unchanged by it.
  double order_confidence = std::numeric_limits<double>::quiet_NaN();
  std::string order_source;
  std::string order_summary;     // one line for the log
};

class StructuredFactorStream {
 public:
  // Throws std::invalid_argument for invalid params (as FactorStream does), centre/learn_order without a
  // window, a window too short for VAR-LiNGAM on two channels (< 10 x 2 x (M + 1) samples) or a negative prune threshold.
  StructuredFactorStream(FactorStreamParams params, StructureSetting setting);

  // Same contract as FactorStream::feed (row i has the source index first_index + i).
  void feed(const Eigen::Ref<const RowMajorMatrix>& block, std::uint64_t first_index, bool discontinuity,
            std::int64_t first_time_ns, double period_ns, std::vector<FactorReport>& out);
  // End of stream: learns on a partial window if still calibrating, then finishes the FactorStream.
  void finish(std::vector<FactorReport>& out);

  const FactorStream* stream() const { return stream_.get(); }  // null while calibrating
  const LearnedStructure& structure() const { return learned_; }
  std::size_t minimum_calibration_samples() const;
  // The shortest window that learns an order for g channels at lag order m: one block of two channels,
  // 10 x min(g, 2) x (m + 1) samples (block_order.hpp: a shorter window than the dense minimum learns
  // the order per block of neighbouring channels).
  static std::size_t minimum_calibration_samples(int g, int lag_order);
  // VAR-LiNGAM's window for one dense order over all g channels: 10 x g x (m + 1) samples.
  static std::size_t dense_calibration_samples(int g, int lag_order);

  // Checkpoint (state_archive.hpp), section "structured_factor_stream". Saved: the configured model and
  // stream parameters and the structure setting (restore throws StateError when this object was built with
  // others), what was learned (centre, causal order, B0, the instantaneous mask in effect, problems), the
  // model the FactorStream runs with and its state (FactorStream::save) once it is built, and the calibration
  // window (samples, discontinuities, times, source indices) while it fills. restore() rebuilds the
  // FactorStream with the learned model before restoring it; on StateError this object is unchanged.
  void save(estimation::StateWriter& w) const;
  void restore(estimation::StateReader& r);

 private:
  void learn(std::vector<FactorReport>& out);
  void feed_centred(const Eigen::Ref<const RowMajorMatrix>& block, std::uint64_t first_index, bool discontinuity,
                    std::int64_t first_time_ns, double period_ns, std::vector<FactorReport>& out);

  FactorStreamParams params_;
  StructureSetting setting_;
  int g_;
  LearnedStructure learned_;
  std::unique_ptr<FactorStream> stream_;
  CalibrationWindow window_;
  RowMajorMatrix scratch_;
};

}  // namespace causal::pipeline
