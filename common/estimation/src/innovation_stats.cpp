#include "causal/estimation/innovation_stats.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"

namespace causal::estimation {

void InnovationAccumulator::add(double e, double s) {
  if (!std::isfinite(e) || !std::isfinite(s) || !(s > 0.0)) return;
  ++count_;
  sum_e_ += e;
  sum_e2_ += e * e;
  sum_nis_ += e * e / s;
}

double InnovationAccumulator::mean() const {
  return count_ ? sum_e_ / static_cast<double>(count_) : std::numeric_limits<double>::quiet_NaN();
}

double InnovationAccumulator::mean_square() const {
  return count_ ? sum_e2_ / static_cast<double>(count_) : std::numeric_limits<double>::quiet_NaN();
}

double InnovationAccumulator::mean_nis() const {
  return count_ ? sum_nis_ / static_cast<double>(count_) : std::numeric_limits<double>::quiet_NaN();
}

void InnovationStats::add(const SvarKalmanFilter& filter) {
  for (int k = 0; k < channels(); ++k) {
    acc_[k].add(filter.last_innovation(k), filter.last_innovation_variance(k));
  }
}

void InnovationStats::reset() {
  for (auto& a : acc_) a.reset();
}

template <class IO, class Self>
void InnovationAccumulator::fields(IO io, Self& a) {
  io.tag("innovation_accumulator", 1);
  io(a.count_, a.sum_e_, a.sum_e2_, a.sum_nis_);
}

void InnovationAccumulator::save(StateWriter& w) const { fields(SaveFields{w}, *this); }

void InnovationAccumulator::restore(StateReader& r) {
  InnovationAccumulator a;
  fields(RestoreFields{r}, a);
  *this = a;
}

void InnovationStats::save(StateWriter& w) const {
  w.begin("innovation_stats", 1);
  w.put(static_cast<std::int32_t>(channels()));
  for (const auto& a : acc_) a.save(w);
}

void InnovationStats::restore(StateReader& r) {
  r.expect("innovation_stats", 1);
  const auto saved = r.get<std::int32_t>();
  if (saved != channels()) {
    throw StateError("checkpoint has innovation statistics of " + std::to_string(saved) + " outcomes, this one has " +
                     std::to_string(channels()));
  }
  std::vector<InnovationAccumulator> acc(acc_.size());
  for (auto& a : acc) a.restore(r);
  acc_ = std::move(acc);
}

}  // namespace causal::estimation
