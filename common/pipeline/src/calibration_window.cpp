#include "causal/pipeline/calibration_window.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

namespace causal::pipeline {

void CalibrationWindow::push(const double* y, bool discontinuity, std::int64_t time_ns, std::uint64_t source_index) {
  values_.insert(values_.end(), y, y + g_);
  disc_.push_back(discontinuity);
  time_.push_back(time_ns);
  index_.push_back(source_index);
}

void CalibrationWindow::clear() {
  values_.clear();
  disc_.clear();
  time_.clear();
  index_.clear();
}

void CalibrationWindow::erase_front(std::size_t n) {
  const auto diff = static_cast<std::ptrdiff_t>(n);
  values_.erase(values_.begin(), values_.begin() + diff * g_);
  disc_.erase(disc_.begin(), disc_.begin() + diff);
  time_.erase(time_.begin(), time_.begin() + diff);
  index_.erase(index_.begin(), index_.begin() + diff);
}

Eigen::Map<const RowMajorMatrix> CalibrationWindow::samples() const {
  return Eigen::Map<const RowMajorMatrix>(values_.data(), static_cast<Eigen::Index>(size()),
                                          static_cast<Eigen::Index>(g_));
}

template <class IO, class Self>
void CalibrationWindow::fields(IO io, Self& w) {
  io(w.values_, w.disc_, w.time_, w.index_);
}

void CalibrationWindow::save(estimation::StateWriter& w) const { fields(estimation::SaveFields{w}, *this); }

CalibrationWindow CalibrationWindow::read(estimation::StateReader& r, const std::string& inconsistent) const {
  CalibrationWindow w(g_);
  fields(estimation::RestoreFields{r}, w);
  const std::size_t n = w.size();
  if (w.values_.size() != n * static_cast<std::size_t>(g_) || w.time_.size() != n || w.index_.size() != n) {
    throw estimation::StateError(inconsistent);
  }
  return w;
}

}  // namespace causal::pipeline
