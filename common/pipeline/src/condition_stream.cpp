#include "causal/pipeline/condition_stream.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_checks.hpp"
#include "causal/estimation/state_fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace causal::pipeline {

Eigen::VectorXd condition_model_input(const Eigen::VectorXd& values, bool log_transform) {
  if (!log_transform) return values;
  Eigen::VectorXd out(values.size());
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    out[i] = values[i] > 0.0 ? std::log(values[i]) : std::numeric_limits<double>::quiet_NaN();
  }
  return out;
}

ConditionStream::ConditionStream(ConditionStreamParams params, int channels)
    : params_(params), channels_(channels), acc_(channels) {
  if (channels < 1) throw std::invalid_argument("condition stream needs at least one channel");
}

void ConditionStream::drop_open_window() {
  if (window_open_) ++dropped_;
  acc_.reset();
  window_open_ = false;
  fed_in_window_ = 0;
  next_discontinuity_ = true;
}

void ConditionStream::close(std::vector<ConditionSample>& out) {
  if (!window_open_) return;
  window_open_ = false;
  fed_in_window_ = 0;
  if (acc_.count() < params_.min_samples) {
    ++dropped_;
    acc_.reset();
    return;
  }
  ConditionSample s;
  s.snapshot_index = params_.window_samples > 0 ? window_first_sample_ / params_.window_samples : window_snapshot_;
  ++produced_;
  s.time_ns = window_time_ns_;
  s.values = acc_.value(params_.feature);
  s.model_input = condition_model_input(s.values, params_.log_transform);
  s.samples = acc_.count();
  s.discontinuity = next_discontinuity_;
  next_discontinuity_ = false;
  acc_.reset();
  out.push_back(std::move(s));
}

void ConditionStream::feed(const double* rows, std::size_t n, std::uint64_t first_sample_index,
                           std::uint64_t snapshot_index, bool discontinuity, bool end_of_segment,
                           std::int64_t first_time_ns, double period_ns, std::vector<ConditionSample>& out) {
  // A new segment closes the previous window (a snapshot whose last frame did not say end_of_segment).
  if (discontinuity) close(out);
  std::size_t done = 0;
  while (done < n) {
    if (!window_open_) {
      window_open_ = true;
      window_time_ns_ = first_time_ns + static_cast<std::int64_t>(std::llround(static_cast<double>(done) * period_ns));
      window_first_sample_ = first_sample_index + done;
      window_snapshot_ = snapshot_index;
    }
    // Fill the open window up to window_samples (counted in rows fed, rejected non-finite rows included).
    std::size_t take = n - done;
    if (params_.window_samples > 0) take = std::min(take, params_.window_samples - fed_in_window_);
    acc_.add(rows + done * static_cast<std::size_t>(channels_), take);
    fed_in_window_ += take;
    done += take;
    if (params_.window_samples > 0 && fed_in_window_ >= params_.window_samples) close(out);
  }
  if (end_of_segment) close(out);
}

template <class IO, class Self>
void ConditionStream::fields(IO io, Self& c) {
  io.object(c.acc_);
  io(c.window_time_ns_, c.window_first_sample_, c.window_snapshot_, c.window_open_);
  io.template as<std::uint64_t>(c.fed_in_window_);
  io(c.next_discontinuity_, c.produced_, c.dropped_);
}

void ConditionStream::save(estimation::StateWriter& w) const {
  w.begin("condition_stream", 1);
  w.put(params_.feature);
  w.put(params_.log_transform);
  w.put(static_cast<std::uint64_t>(params_.window_samples));
  w.put(static_cast<std::uint64_t>(params_.min_samples));
  w.put(static_cast<std::int32_t>(channels_));
  fields(estimation::SaveFields{w}, *this);
}

void ConditionStream::restore(estimation::StateReader& r) {
  r.expect("condition_stream", 1);
  const std::string me = "condition stream";
  const auto feature = r.get<io::ConditionFeature>();
  if (feature != params_.feature) {
    throw estimation::StateError("checkpoint has condition feature " + io::to_string(feature) + ", this " + me + " has " +
                     io::to_string(params_.feature));
  }
  estimation::expect_saved(r, "log transform", params_.log_transform, me);
  estimation::expect_saved(r, "window_samples", static_cast<std::uint64_t>(params_.window_samples), me);
  estimation::expect_saved(r, "min_samples", static_cast<std::uint64_t>(params_.min_samples), me);
  const auto g = r.get<std::int32_t>();
  if (g != channels_) {
    throw estimation::StateError("checkpoint has " + std::to_string(g) + " channels, this " + me + " has " +
                     std::to_string(channels_));
  }
  // Into copies first: on StateError this stream stays as it was.
  ConditionStream c(params_, channels_);
  fields(estimation::RestoreFields{r}, c);
  if (params_.window_samples > 0 && c.fed_in_window_ >= params_.window_samples) {
    throw estimation::StateError("checkpoint: condition window fill out of range");
  }
  *this = std::move(c);
}

}  // namespace causal::pipeline
