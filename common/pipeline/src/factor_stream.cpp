#include "causal/pipeline/factor_stream.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"
#include "causal/estimation/state_checks.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace causal::pipeline {
namespace {

// validate_noise_params without the exception: tuned values come from data, not from the parameters.
bool valid_noise(const estimation::NoiseParams& n) {
  return std::isfinite(n.q) && n.q >= 0.0 && std::isfinite(n.r) && n.r > 0.0 && std::isfinite(n.p0) && n.p0 > 0.0;
}

// Standard deviations that are 0 (a variance <= 0 clamped) or not finite: the outcome lost precision.
std::uint32_t degenerate_entries(const Eigen::VectorXd& std_devs) {
  std::uint32_t n = 0;
  for (Eigen::Index i = 0; i < std_devs.size(); ++i) n += !(std_devs[i] > 0.0 && std::isfinite(std_devs[i]));
  return n;
}

}  // namespace

namespace {

// One field list each for save and restore (SaveFields / RestoreFields, state_fields.hpp).
template <class Io, class N>
void noise_fields(Io io, N& n) {
  io(n.q, n.r, n.p0);
}

template <class Io, class R>
void report_fields(Io io, R& r) {
  io(r.kind);
  io(r.outcome);  // as an int32 (static_assert below)
  io(r.sample_index, r.time_ns, r.factors, r.std_devs, r.covariance, r.innovation_count, r.innovation_mean, r.nis_mean,
     r.last_innovation, r.last_innovation_variance, r.rejected, r.q, r.r);
}

static_assert(sizeof(int) == sizeof(std::int32_t), "checkpoints store FactorReport::outcome as 4 bytes");

template <class Io, class T>
void tuning_fields(Io io, T& t) {
  noise_fields(io, t.noise);
  io(t.log_likelihood);
  io.template as<std::int32_t>(t.evaluations);
  io(t.converged, t.message, t.at_range_limit);
  io.template as<std::int64_t>(t.updates);
}

// A filter report waiting for its twin: where it stands (its reports follow, with their count).
template <class Io, class P>
void pending_fields(Io io, P& p) {
  io(p.index, p.time_ns);
}

void put_noise(estimation::StateWriter& w, const estimation::NoiseParams& n) { noise_fields(estimation::SaveFields{w}, n); }

estimation::NoiseParams get_noise(estimation::StateReader& r) {
  estimation::NoiseParams n;
  noise_fields(estimation::RestoreFields{r}, n);
  return n;
}

void put_report(estimation::StateWriter& w, const FactorReport& r) { report_fields(estimation::SaveFields{w}, r); }

FactorReport get_report(estimation::StateReader& in) {
  FactorReport r;
  report_fields(estimation::RestoreFields{in}, r);
  return r;
}

}  // namespace

namespace {

// The parameters a stream's state depends on: saved with it, and on restore compared with the stream's own.
template <class Io>
void stream_param_fields(Io io, const FactorStreamParams& params, const char* owner) {
  io.same(params.noise.automatic, "automatic noise", owner);
  io.same(params.noise.fixed.q, "configured q", owner);
  io.same(params.noise.fixed.r, "configured r", owner);
  io.same(params.noise.fixed.p0, "configured p0", owner);
  io.template same_as<std::uint64_t>(params.noise.calibration_samples, "calibration_samples", owner);
  io.template same_as<std::uint64_t>(params.publish_every, "publish_every", owner);
  io.template same_as<std::int32_t>(params.fixed_lag, "fixed lag", owner);
}

}  // namespace

void save_stream_params(estimation::StateWriter& w, const FactorStreamParams& params) {
  stream_param_fields(estimation::SaveFields{w}, params, "");
}

void expect_same_stream_params(estimation::StateReader& r, const FactorStreamParams& params, const std::string& owner) {
  stream_param_fields(estimation::RestoreFields{r}, params, owner.c_str());
}

std::size_t FactorStream::minimum_noise_calibration_samples(const estimation::ModelSpec& model) {
  // The likelihood needs clearly more usable samples than factors per outcome.
  return 10 * static_cast<std::size_t>(estimation::SvarLayout(model).factor_count(0)) + 10;
}

FactorStream::FactorStream(FactorStreamParams params)
    : params_(std::move(params)),
      layout_(params_.model),
      g_(layout_.channels()),
      stats_(layout_.channels()),
      window_(layout_.channels()) {
  if (params_.publish_every == 0) throw std::invalid_argument("publish_every must be >= 1");
  if (params_.fixed_lag < 0) throw std::invalid_argument("fixed_lag must be >= 0");
  estimation::validate_noise_params(params_.noise.fixed, "noise");
  const auto f = static_cast<Eigen::Index>(layout_.total_factors());
  all_factors_.resize(f);
  all_std_.resize(f);
  if (params_.noise.automatic) {
    const std::size_t minimum = minimum_noise_calibration_samples(params_.model);
    if (params_.noise.calibration_samples < minimum) {
      throw std::invalid_argument("calibration_samples must be >= " + std::to_string(minimum) +
                                  " for this model (10 x factors per outcome + 10)");
    }
  } else {
    noise_.assign(static_cast<std::size_t>(g_), params_.noise.fixed);
    smoother_ = std::make_unique<estimation::FixedLagSmoother>(layout_, noise_, params_.fixed_lag, params_.publish_every);
  }
}

estimation::FilterCounters FactorStream::counters() const {
  return smoother_ ? smoother_->filter().counters() : estimation::FilterCounters{};
}

void FactorStream::feed(const Eigen::Ref<const RowMajorMatrix>& block, std::uint64_t first_index, bool discontinuity,
                        std::int64_t first_time_ns, double period_ns, std::vector<FactorReport>& out) {
  if (block.cols() != g_) {
    throw std::invalid_argument("block has " + std::to_string(block.cols()) + " channels, the model has " +
                                std::to_string(g_));
  }
  poll_tuning(out);
  for (Eigen::Index row = 0; row < block.rows(); ++row) {
    const double* y = block.data() + row * block.outerStride();
    const bool disc = discontinuity && row == 0;
    const std::int64_t t = row_time_ns(first_time_ns, row, period_ns);
    const std::uint64_t source_index = first_index + static_cast<std::uint64_t>(row);
    ++buffered_index_;
    if (smoother_ && window_.empty()) {
      process(y, disc, t, source_index, out);
      continue;
    }
    window_.push(y, disc, t, source_index);
    if (smoother_) continue;  // behind the window's replay, in order
    if (tuning_job_.valid()) {
      if (window_.size() >= NoiseSetting::kWorkerBufferFactor * params_.noise.calibration_samples) calibrate(out);
      continue;
    }
    if (window_.size() < params_.noise.calibration_samples) continue;
    if (params_.noise.worker) {
      start_tuning();
    } else {
      calibrate(out);
    }
  }
  replay(static_cast<std::size_t>(block.rows()), out);
}

void FactorStream::replay(std::size_t fed_rows, std::vector<FactorReport>& out) {
  if (!smoother_ || window_.empty()) return;
  const std::size_t share =
      params_.noise.worker ? fed_rows + std::max<std::size_t>(1, params_.noise.calibration_samples / NoiseSetting::kReplayShare)
                           : window_.size();
  window_.replay_front(share, [&](const double* y, bool disc, std::int64_t t, std::uint64_t source_index) {
    process(y, disc, t, source_index, out);
  });
}

namespace {

// The tuning's input: the window's first `rows` samples (the calibration window proper; while a worker tunes,
// the window also buffers what came after it).
std::vector<estimation::NoiseTuningResult> tune_window(const estimation::SvarLayout& layout, const Eigen::MatrixXd& samples,
                                           const std::vector<bool>& disc, double p0) {
  estimation::NoiseTuningOptions options;
  options.p0 = p0;
  return estimation::tune_noise_all(layout, samples, disc, options);
}

}  // namespace

void FactorStream::start_tuning() {
  const auto rows = static_cast<Eigen::Index>(params_.noise.calibration_samples);
  Eigen::MatrixXd samples = window_.samples().topRows(rows);
  std::vector<bool> disc(window_.discontinuities().begin(), window_.discontinuities().begin() + rows);
  tuning_job_ = params_.noise.worker->submit(
      [layout = layout_, samples = std::move(samples), disc = std::move(disc), p0 = params_.noise.fixed.p0] {
        return tune_window(layout, samples, disc, p0);
      });
}

void FactorStream::poll_tuning(std::vector<FactorReport>& out) {
  if (!tuning_job_.valid()) return;
  if (tuning_job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
  install_tuning(tuning_job_.get(), out);
}

void FactorStream::calibrate(std::vector<FactorReport>& out) {
  if (tuning_job_.valid()) {
    install_tuning(tuning_job_.get(), out);
    return;
  }
  // At most calibration_samples: a stream restored from a checkpoint taken while its worker tuned holds more.
  const auto rows = static_cast<Eigen::Index>(std::min(window_.size(), params_.noise.calibration_samples));
  const std::vector<bool> disc(window_.discontinuities().begin(), window_.discontinuities().begin() + rows);
  install_tuning(tune_window(layout_, window_.samples().topRows(rows), disc, params_.noise.fixed.p0), out);
}

void FactorStream::install_tuning(std::vector<estimation::NoiseTuningResult> tuning, std::vector<FactorReport>& out) {
  tuning_ = std::move(tuning);
  noise_.clear();
  for (int k = 0; k < g_; ++k) {
    // A window that cannot be tuned (too few usable samples, a dead outcome, absurd values, no finite
    // likelihood) must not stop the stream: keep the configured values for that outcome and say so.
    const auto& t = tuning_[static_cast<std::size_t>(k)];
    const bool tuned = t.usable && t.evaluations > 0 && valid_noise(t.noise);
    noise_.push_back(tuned ? t.noise : params_.noise.fixed);
    if (!tuned) {
      warnings_.push_back("outcome " + std::to_string(k + 1) + ": automatic noise failed, configured noise (q = " +
                          std::to_string(params_.noise.fixed.q) + ", r = " + std::to_string(params_.noise.fixed.r) +
                          ") used: " + t.message);
    }
  }
  smoother_ = std::make_unique<estimation::FixedLagSmoother>(layout_, noise_, params_.fixed_lag, params_.publish_every);
  // The calibration window is replayed so no sample is lost: at once on the feeding thread, with a worker a share
  // per feed (replay()).
  if (!params_.noise.worker) replay(0, out);
}

void FactorStream::process(const double* y, bool discontinuity, std::int64_t time_ns, std::uint64_t source_index,
                           std::vector<FactorReport>& out) {
  std::uint64_t released_index = 0;
  const bool released =
      smoother_->step_into(y, discontinuity, &released_index, all_factors_.data(), all_std_.data());
  if (smoother_->last_status() == estimation::SampleStatus::Updated) stats_.add(smoother_->filter());
  const std::uint64_t index = next_index_++;
  if (released && params_.fixed_lag > 0) {
    emit_smoothed(estimation::SmoothedSample{released_index, all_factors_, all_std_}, out);
  }
  if (++since_report_ >= params_.publish_every) {
    since_report_ = 0;
    emit_filter(index, source_index, time_ns, out);
  }
}

FactorReport FactorStream::make_report(EstimateKind kind, int k, std::uint64_t index, std::int64_t time_ns,
                                       const Eigen::VectorXd& all_factors, const Eigen::VectorXd& all_std) const {
  FactorReport r;
  r.kind = kind;
  r.outcome = k;
  r.sample_index = index;
  r.time_ns = time_ns;
  const auto off = static_cast<Eigen::Index>(layout_.offset(k));
  const auto d = static_cast<Eigen::Index>(layout_.factor_count(k));
  r.factors = all_factors.segment(off, d);
  r.std_devs = all_std.segment(off, d);
  r.degenerate_std = degenerate_entries(r.std_devs);
  r.rejected = smoother_->filter().counters().rejected_non_finite;
  r.q = noise_[static_cast<std::size_t>(k)].q;
  r.r = noise_[static_cast<std::size_t>(k)].r;
  return r;
}

void FactorStream::emit_filter(std::uint64_t index, std::uint64_t source_index, std::int64_t time_ns,
                               std::vector<FactorReport>& out) {
  const auto& filter = smoother_->filter();
  Eigen::VectorXd factors(all_factors_.size()), stds(all_std_.size());
  filter.estimates(factors.data());
  filter.std_devs(stds.data());
  Pending pending{index, time_ns, {}};
  for (int k = 0; k < g_; ++k) {
    FactorReport r = make_report(EstimateKind::Filter, k, source_index, time_ns, factors, stds);
    // The filter's P is block-diagonal by outcome, so P_k is the whole covariance of this report's factors.
    r.covariance = filter.covariance(k);
    const auto& acc = stats_.outcome(k);
    r.innovation_count = acc.count();
    r.innovation_mean = acc.mean();
    r.nis_mean = acc.mean_nis();
    r.last_innovation = filter.last_innovation(k);
    r.last_innovation_variance = filter.last_innovation_variance(k);
    if (params_.fixed_lag > 0) pending.filter_reports.push_back(r);
    out.push_back(std::move(r));
  }
  stats_.reset();
  if (params_.fixed_lag > 0) pending_.push_back(std::move(pending));
}

void FactorStream::emit_smoothed(const estimation::SmoothedSample& s, std::vector<FactorReport>& out) {
  // Only the indices that got a filter report get a smoothed twin (same cadence on both topics).
  while (!pending_.empty() && pending_.front().index < s.index) pending_.pop_front();
  if (pending_.empty() || pending_.front().index != s.index) return;
  const Pending& p = pending_.front();
  for (int k = 0; k < g_; ++k) {
    const FactorReport& twin = p.filter_reports[static_cast<std::size_t>(k)];
    FactorReport r = make_report(EstimateKind::FixedLag, k, twin.sample_index, p.time_ns, s.estimates, s.std_devs);
    r.innovation_count = twin.innovation_count;
    r.innovation_mean = twin.innovation_mean;
    r.nis_mean = twin.nis_mean;
    r.last_innovation = twin.last_innovation;
    r.last_innovation_variance = twin.last_innovation_variance;
    out.push_back(std::move(r));
  }
  pending_.pop_front();
}

void FactorStream::finish(std::vector<FactorReport>& out) {
  if (!smoother_) {
    if (window_.empty()) return;
    calibrate(out);
  }
  window_.replay_and_clear([&](const double* y, bool disc, std::int64_t t, std::uint64_t source_index) {
    process(y, disc, t, source_index, out);
  });
  for (const estimation::SmoothedSample& s : smoother_->flush()) {
    if (params_.fixed_lag > 0) emit_smoothed(s, out);
  }
}

void FactorStream::save(estimation::StateWriter& w) const {
  w.begin("factor_stream", 1);
  estimation::save_model_spec(w, params_.model);
  save_stream_params(w, params_);

  w.put(calibrated());
  if (calibrated()) {
    for (const estimation::NoiseParams& n : noise_) put_noise(w, n);
    smoother_->save(w);
  }
  w.put(static_cast<std::uint64_t>(tuning_.size()));
  for (const estimation::NoiseTuningResult& t : tuning_) tuning_fields(estimation::SaveFields{w}, t);
  stats_.save(w);
  window_.save(w);
  w.put(static_cast<std::uint64_t>(pending_.size()));
  for (const Pending& p : pending_) {
    pending_fields(estimation::SaveFields{w}, p);
    w.put(static_cast<std::uint64_t>(p.filter_reports.size()));
    for (const FactorReport& r : p.filter_reports) put_report(w, r);
  }
  w.put(next_index_);
  w.put(buffered_index_);
  w.put(static_cast<std::uint64_t>(since_report_));
}

void FactorStream::restore(estimation::StateReader& r) {
  r.expect("factor_stream", 1);
  const std::string me = "factor stream";
  estimation::expect_same_model(estimation::read_model_spec(r), params_.model, me);
  expect_same_stream_params(r, params_, me);

  // Everything into locals first: on StateError this stream stays as it was.
  std::vector<estimation::NoiseParams> noise;
  std::unique_ptr<estimation::FixedLagSmoother> smoother;
  if (r.get<bool>()) {
    for (int k = 0; k < g_; ++k) noise.push_back(get_noise(r));
    try {
      smoother = std::make_unique<estimation::FixedLagSmoother>(layout_, noise, params_.fixed_lag, params_.publish_every);
    } catch (const std::invalid_argument& e) {
      throw estimation::StateError(std::string("checkpoint holds invalid noise: ") + e.what());
    }
    smoother->restore(r);
  } else if (!params_.noise.automatic) {
    throw estimation::StateError("checkpoint: an uncalibrated stream with configured noise");
  }
  const auto n_tuning = r.get<std::uint64_t>();
  if (n_tuning != 0 && n_tuning != static_cast<std::uint64_t>(g_)) throw estimation::StateError("checkpoint: tuning of another shape");
  std::vector<estimation::NoiseTuningResult> tuning(static_cast<std::size_t>(n_tuning));
  for (estimation::NoiseTuningResult& t : tuning) tuning_fields(estimation::RestoreFields{r}, t);
  estimation::InnovationStats stats(g_);
  stats.restore(r);
  const std::string inconsistent = "checkpoint: inconsistent calibration buffer of the factor stream";
  CalibrationWindow window = window_.read(r, inconsistent);
  // A calibrated stream holds a window only while replaying it (automatic noise).
  if (smoother && !window.empty() && !params_.noise.automatic) throw estimation::StateError(inconsistent);
  // Filter reports wait at most `fixed_lag` samples for their twin: at most fixed_lag + 1 are pending.
  const auto n_pending = r.get<std::uint64_t>();
  if (n_pending > static_cast<std::uint64_t>(params_.fixed_lag) + 1) throw estimation::StateError("checkpoint: too many pending reports");
  std::deque<Pending> pending(static_cast<std::size_t>(n_pending));
  for (Pending& p : pending) {
    pending_fields(estimation::RestoreFields{r}, p);
    const auto n = r.get<std::uint64_t>();
    if (n != static_cast<std::uint64_t>(g_)) throw estimation::StateError("checkpoint: pending report of another shape");
    for (std::uint64_t k = 0; k < n; ++k) p.filter_reports.push_back(get_report(r));
  }
  const auto next_index = r.get<std::uint64_t>();
  const auto buffered_index = r.get<std::uint64_t>();
  const auto since_report = r.get<std::uint64_t>();
  if (since_report >= params_.publish_every) throw estimation::StateError("checkpoint: factor stream report counter out of range");

  tuning_job_ = {};  // a tuning still running for the replaced state is not used (it finishes on the worker)
  noise_ = std::move(noise);
  tuning_ = std::move(tuning);
  smoother_ = std::move(smoother);
  stats_ = std::move(stats);
  window_ = std::move(window);
  pending_ = std::move(pending);
  next_index_ = next_index;
  buffered_index_ = buffered_index;
  since_report_ = static_cast<std::size_t>(since_report);
}

}  // namespace causal::pipeline
