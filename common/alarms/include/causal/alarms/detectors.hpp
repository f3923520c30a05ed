// Building blocks of the alarm engine: a clipped, capped one-sided CUSUM, a sliding-window mean and a
// persistence / hysteresis latch. Each is a small value type with no allocation after construction
// (the window preallocates), so the engine can hold one per channel and signal.
#pragma once

#include <cstdint>
#include <vector>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::alarms {

// One-sided upper CUSUM on a standardised signal z (baseline ~ N(0,1)):
//   S_n = min(cap, max(0, S_{n-1} + min(z_n, clip) - k))
// * k (reference value) = half the shift, in baseline sigmas, the chart is tuned to detect fastest.
// * clip (Huber-type winsorising): one observation adds at most clip - k, so with h > clip - k a single
//   spike, however large, can never cross h: at least two anomalous observations are needed. It also
//   bounds the influence of heavy baseline tails, which makes Siegmund's Gaussian ARL0 conservative.
// * cap: an upper ceiling on S (a "capped CUSUM") so that after a long fault the statistic returns
//   below the clear level within about (cap - clear) / k observations once the signal is back to
//   normal, instead of draining for as long as the fault lasted.
// The start of the current excursion (first observation after the last S = 0) is the classical CUSUM
// change-point estimate; the root-cause logic compares these onsets between channels.
class ClippedCusum {
 public:
  ClippedCusum() = default;
  ClippedCusum(double k, double clip, double cap);

  // Feeds one standardised value; returns the new statistic. Non-finite z leaves the state unchanged.
  double update(double z, std::uint64_t index, std::int64_t time_ns);
  void reset();

  double value() const { return s_; }
  bool in_excursion() const { return s_ > 0.0; }
  std::uint64_t onset_index() const { return onset_index_; }  // valid while in_excursion()
  std::int64_t onset_time_ns() const { return onset_time_ns_; }

  // Checkpoint of the whole state, settings included, so the restored chart continues bit for bit.
  // restore() throws estimation::StateError on a truncated or foreign section.
  void save(estimation::StateWriter& out) const;
  void restore(estimation::StateReader& in);

 private:
  // The checkpoint's one field list (SaveFields / RestoreFields, state_fields.hpp): Self is const when saving.
  template <class IO, class Self>
  static void fields(IO io, Self& self);
  double k_ = 1.0, clip_ = 4.0, cap_ = 1e300;
  double s_ = 0.0;
  std::uint64_t onset_index_ = 0;
  std::int64_t onset_time_ns_ = 0;
};

// Mean of the last `window` finite values pushed (fewer while filling).
class WindowMean {
 public:
  WindowMean() = default;
  explicit WindowMean(int window);
  void push(double v);  // non-finite values are ignored
  void reset();
  double mean() const;  // NaN when empty
  int count() const { return count_; }
  bool full() const { return count_ == static_cast<int>(buf_.size()); }
  int window() const { return static_cast<int>(buf_.size()); }
  double median() const;  // median of the values in the window (NaN when empty)

  // Checkpoint of the buffer and the running sum as they are (not recomputed: the restored window must
  // give the same rounding as the uninterrupted one). restore() throws estimation::StateError on a truncated,
  // foreign or inconsistent section.
  void save(estimation::StateWriter& out) const;
  void restore(estimation::StateReader& in);

 private:
  // The checkpoint's one field list (SaveFields / RestoreFields, state_fields.hpp): Self is const when saving.
  template <class IO, class Self>
  static void fields(IO io, Self& self);
  std::vector<double> buf_;
  int next_ = 0, count_ = 0;
  double sum_ = 0.0;
};

// Persistence and hysteresis for one alarm:
// * raise when the statistic has been >= the raise threshold for `raise_count` consecutive observations;
// * clear when it has been < the clear threshold (<= raise threshold) for `clear_count` consecutive ones.
// Observations without a value (missing data) neither advance nor reset the counters.
class PersistenceLatch {
 public:
  enum class Transition { None, Raise, Clear };
  PersistenceLatch() = default;
  PersistenceLatch(int raise_count, int clear_count);
  Transition update(double statistic, double raise_threshold, double clear_threshold);
  bool active() const { return active_; }
  int above_count() const { return above_; }
  int below_count() const { return below_; }
  void reset();
  // Raises without a statistic: the decision was taken elsewhere (an abrupt rise confirmed as progressive
  // after its confirmation window, see AlarmParams::confirmation_observations).
  void force_raise();

  // Checkpoint of the counts and the latch (a restored active alarm keeps its hysteresis progress).
  void save(estimation::StateWriter& out) const;
  void restore(estimation::StateReader& in);

 private:
  // The checkpoint's one field list (SaveFields / RestoreFields, state_fields.hpp): Self is const when saving.
  template <class IO, class Self>
  static void fields(IO io, Self& self);
  int raise_count_ = 1, clear_count_ = 1;
  int above_ = 0, below_ = 0;
  bool active_ = false;
};

}  // namespace causal::alarms
