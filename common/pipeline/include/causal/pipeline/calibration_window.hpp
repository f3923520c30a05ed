// The samples a stream holds back while it calibrates on the start of its input (FactorStream: automatic
// noise; StructuredFactorStream: the centre and the causal order): the values and, per sample, its
// discontinuity flag, UTC time and source index, so the window can be replayed as received once the
// calibration is done and no sample is lost to it. Saved and restored with the stream that owns it.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "causal/estimation/state_archive_fwd.hpp"

namespace causal::pipeline {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Time of row `row` of a block whose row 0 is at first_time_ns and whose rows are period_ns apart.
inline std::int64_t row_time_ns(std::int64_t first_time_ns, Eigen::Index row, double period_ns) {
  return first_time_ns + static_cast<std::int64_t>(std::llround(static_cast<double>(row) * period_ns));
}

class CalibrationWindow {
 public:
  explicit CalibrationWindow(int channels) : g_(channels) {}

  void push(const double* y, bool discontinuity, std::int64_t time_ns, std::uint64_t source_index);
  std::size_t size() const { return disc_.size(); }
  bool empty() const { return disc_.empty(); }
  void clear();

  // The window as a size() x G matrix (a view: valid until the next push or clear).
  Eigen::Map<const RowMajorMatrix> samples() const;
  const std::vector<bool>& discontinuities() const { return disc_; }

  // Calls f(y, discontinuity, time_ns, source_index) for every sample in the order received, then empties
  // the window.
  template <class F>
  void replay_and_clear(F&& f) {
    for (std::size_t i = 0; i < size(); ++i) f(values_.data() + i * static_cast<std::size_t>(g_), disc_[i], time_[i], index_[i]);
    clear();
  }

  // The same for the first n samples (at most size()), which are then removed; the rest stays, in order.
  template <class F>
  void replay_front(std::size_t n, F&& f) {
    n = n < size() ? n : size();
    const auto g = static_cast<std::size_t>(g_);
    for (std::size_t i = 0; i < n; ++i) f(values_.data() + i * g, disc_[i], time_[i], index_[i]);
    erase_front(n);
  }

  // Checkpoint: the values, the discontinuities, the times and the source indices, in that order.
  void save(estimation::StateWriter& w) const;
  // Reads what save() wrote into a window of the same channel count; throws StateError(`inconsistent`) when
  // the parts disagree in length. `this` is unchanged (assign the result when every other part is read).
  CalibrationWindow read(estimation::StateReader& r, const std::string& inconsistent) const;

 private:
  // The checkpoint's one field list (SaveFields / RestoreFields, state_fields.hpp): Self is const when saving.
  template <class IO, class Self>
  static void fields(IO io, Self& self);
  void erase_front(std::size_t n);
  int g_;
  std::vector<double> values_;       // row-major, G per sample
  std::vector<bool> disc_;
  std::vector<std::int64_t> time_;
  std::vector<std::uint64_t> index_;  // source indices
};

}  // namespace causal::pipeline
