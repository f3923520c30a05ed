// Streaming innovation statistics for services that publish diagnostics every N samples.
// For a correctly tuned filter the innovations are white with E[e] = 0 and E[e^2 / S] = 1 (normalised
// innovation squared, NIS; Bar-Shalom, Li & Kirubarajan, "Estimation with Applications to Tracking and
// Navigation", 2001, sec. 5.4): mean_nis() >> 1 means r or q is too small, << 1 too large.
#pragma once

#include <cstdint>
#include <vector>

namespace causal::estimation {

class SvarKalmanFilter;
class StateWriter;
class StateReader;

class InnovationAccumulator {
 public:
  // Adds one innovation e with variance s. Non-finite e or s, or s <= 0, is ignored (not counted).
  void add(double e, double s);
  void reset() { *this = InnovationAccumulator{}; }
  std::uint64_t count() const { return count_; }
  double mean() const;                // mean e          (NaN when empty)
  double mean_square() const;         // mean e^2        (NaN when empty)
  double mean_nis() const;            // mean e^2 / s    (NaN when empty)

  // Checkpoint: the count and the three running sums (section "innovation_accumulator").
  void save(StateWriter& w) const;
  void restore(StateReader& r);

 private:
  // The checkpoint's one field list (SaveFields / RestoreFields, state_fields.hpp): Self is const when saving.
  template <class IO, class Self>
  static void fields(IO io, Self& self);
  std::uint64_t count_ = 0;
  double sum_e_ = 0.0, sum_e2_ = 0.0, sum_nis_ = 0.0;
};

// One accumulator per outcome, fed from a filter after each Updated step.
class InnovationStats {
 public:
  explicit InnovationStats(int channels) : acc_(channels) {}
  void add(const SvarKalmanFilter& filter);  // adds last_innovation(k), last_innovation_variance(k) for all k
  const InnovationAccumulator& outcome(int k) const { return acc_.at(k); }
  int channels() const { return static_cast<int>(acc_.size()); }
  void reset();

  // Checkpoint (section "innovation_stats"): the channel count (restore throws StateError when it differs)
  // and every outcome's accumulator.
  void save(StateWriter& w) const;
  void restore(StateReader& r);

 private:
  std::vector<InnovationAccumulator> acc_;
};

}  // namespace causal::estimation
