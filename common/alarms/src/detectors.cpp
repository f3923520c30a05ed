#include "causal/alarms/detectors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "causal/alarms/statistics.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

namespace causal::alarms {

ClippedCusum::ClippedCusum(double k, double clip, double cap) : k_(k), clip_(clip), cap_(cap) {
  if (!(k > 0.0)) throw std::invalid_argument("ClippedCusum: k must be > 0");
  if (!(clip > k)) throw std::invalid_argument("ClippedCusum: clip must be > k (else S can never grow)");
  if (!(cap > 0.0)) throw std::invalid_argument("ClippedCusum: cap must be > 0");
}

double ClippedCusum::update(double z, std::uint64_t index, std::int64_t time_ns) {
  if (!std::isfinite(z)) return s_;
  const double increment = std::min(z, clip_) - k_;
  if (s_ <= 0.0 && increment > 0.0) {
    onset_index_ = index;  // new excursion: the change-point estimate is its first observation
    onset_time_ns_ = time_ns;
  }
  s_ = std::min(cap_, std::max(0.0, s_ + increment));
  return s_;
}

void ClippedCusum::reset() {
  s_ = 0.0;
  onset_index_ = 0;
  onset_time_ns_ = 0;
}

template <class IO, class Self>
void ClippedCusum::fields(IO io, Self& c) {
  io.tag("clipped_cusum", 1);
  io(c.k_, c.clip_, c.cap_, c.s_, c.onset_index_, c.onset_time_ns_);
}

void ClippedCusum::save(estimation::StateWriter& out) const { fields(estimation::SaveFields{out}, *this); }

void ClippedCusum::restore(estimation::StateReader& in) {
  ClippedCusum c;
  fields(estimation::RestoreFields{in}, c);
  // The constructor's promises (k > 0, clip > k, cap > 0) and a statistic inside [0, cap].
  if (!(c.k_ > 0.0 && c.clip_ > c.k_ && c.cap_ > 0.0 && c.s_ >= 0.0 && c.s_ <= c.cap_)) {
    throw estimation::StateError("checkpoint: clipped_cusum section holds invalid values");
  }
  *this = c;
}

WindowMean::WindowMean(int window) {
  if (window < 1) throw std::invalid_argument("WindowMean: window must be >= 1");
  buf_.assign(static_cast<std::size_t>(window), 0.0);
}

void WindowMean::push(double v) {
  if (!std::isfinite(v) || buf_.empty()) return;
  if (full()) sum_ -= buf_[static_cast<std::size_t>(next_)];
  buf_[static_cast<std::size_t>(next_)] = v;
  sum_ += v;
  next_ = (next_ + 1) % static_cast<int>(buf_.size());
  if (!full()) ++count_;
  // Recompute the sum from scratch once per wrap so rounding error cannot accumulate without bound.
  if (next_ == 0) {
    sum_ = 0.0;
    for (int i = 0; i < count_; ++i) sum_ += buf_[static_cast<std::size_t>(i)];
  }
}

void WindowMean::reset() {
  std::fill(buf_.begin(), buf_.end(), 0.0);
  next_ = count_ = 0;
  sum_ = 0.0;
}

double WindowMean::mean() const {
  if (count_ == 0) return std::numeric_limits<double>::quiet_NaN();
  return sum_ / count_;
}

double WindowMean::median() const {
  if (count_ == 0) return std::numeric_limits<double>::quiet_NaN();
  // While filling, the values live in buf_[0 .. count_); once full, all of buf_ is in use.
  return causal::alarms::median(std::vector<double>(buf_.begin(), buf_.begin() + count_));
}

template <class IO, class Self>
void WindowMean::fields(IO io, Self& w) {
  io.tag("window_mean", 1);
  io(w.buf_, w.next_, w.count_, w.sum_);
}

void WindowMean::save(estimation::StateWriter& out) const { fields(estimation::SaveFields{out}, *this); }

void WindowMean::restore(estimation::StateReader& in) {
  WindowMean w;
  fields(estimation::RestoreFields{in}, w);
  const int n = static_cast<int>(w.buf_.size());
  if (w.next_ < 0 || w.count_ < 0 || w.count_ > n || (n > 0 && w.next_ >= n) || (n == 0 && w.next_ != 0)) {
    throw estimation::StateError("checkpoint: window_mean section is inconsistent (position outside the window)");
  }
  *this = std::move(w);
}

PersistenceLatch::PersistenceLatch(int raise_count, int clear_count)
    : raise_count_(raise_count), clear_count_(clear_count) {
  if (raise_count < 1 || clear_count < 1) throw std::invalid_argument("PersistenceLatch: counts must be >= 1");
}

PersistenceLatch::Transition PersistenceLatch::update(double statistic, double raise_threshold,
                                                      double clear_threshold) {
  if (!std::isfinite(statistic)) return Transition::None;
  if (!active_) {
    above_ = statistic >= raise_threshold ? above_ + 1 : 0;
    if (above_ >= raise_count_) {
      active_ = true;
      above_ = below_ = 0;
      return Transition::Raise;
    }
    return Transition::None;
  }
  below_ = statistic < clear_threshold ? below_ + 1 : 0;
  if (below_ >= clear_count_) {
    active_ = false;
    above_ = below_ = 0;
    return Transition::Clear;
  }
  return Transition::None;
}

void PersistenceLatch::force_raise() {
  active_ = true;
  above_ = below_ = 0;
}

void PersistenceLatch::reset() {
  above_ = below_ = 0;
  active_ = false;
}

template <class IO, class Self>
void PersistenceLatch::fields(IO io, Self& l) {
  io.tag("persistence_latch", 1);
  io(l.raise_count_, l.clear_count_, l.above_, l.below_, l.active_);
}

void PersistenceLatch::save(estimation::StateWriter& out) const { fields(estimation::SaveFields{out}, *this); }

void PersistenceLatch::restore(estimation::StateReader& in) {
  PersistenceLatch l;
  fields(estimation::RestoreFields{in}, l);
  if (l.raise_count_ < 1 || l.clear_count_ < 1 || l.above_ < 0 || l.below_ < 0) {
    throw estimation::StateError("checkpoint: persistence_latch section holds invalid counts");
  }
  *this = l;
}

}  // namespace causal::alarms
