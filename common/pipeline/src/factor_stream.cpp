#include "causal/pipeline/factor_stream.hpp"

#include <cmath>
#include <stdexcept>

namespace causal::pipeline {
namespace {

// validate_noise_params without the exception: tuned values come from data, not from the parameters.
bool valid_noise(const NoiseParams& n) {
  return std::isfinite(n.q) && n.q >= 0.0 && std::isfinite(n.r) && n.r > 0.0 && std::isfinite(n.p0) && n.p0 > 0.0;
}

// Standard deviations that are 0 (a variance <= 0 clamped) or not finite: the outcome lost precision.
std::uint32_t degenerate_entries(const Eigen::VectorXd& std_devs) {
  std::uint32_t n = 0;
  for (Eigen::Index i = 0; i < std_devs.size(); ++i) n += !(std_devs[i] > 0.0 && std::isfinite(std_devs[i]));
  return n;
}

}  // namespace

FactorStream::FactorStream(FactorStreamParams params)
    : params_(std::move(params)), layout_(params_.model), g_(layout_.channels()), stats_(layout_.channels()) {
  if (params_.publish_every == 0) throw std::invalid_argument("publish_every must be >= 1");
  if (params_.fixed_lag < 0) throw std::invalid_argument("fixed_lag must be >= 0");
  validate_noise_params(params_.noise.fixed, "noise");
  const auto f = static_cast<Eigen::Index>(layout_.total_factors());
  all_factors_.resize(f);
  all_std_.resize(f);
  if (params_.noise.automatic) {
    // The likelihood needs clearly more usable samples than factors per outcome.
    const std::size_t minimum = 10 * static_cast<std::size_t>(layout_.factor_count(0)) + 10;
    if (params_.noise.calibration_samples < minimum) {
      throw std::invalid_argument("calibration_samples must be >= " + std::to_string(minimum) +
                                  " for this model (10 x factors per outcome + 10)");
    }
  } else {
    noise_.assign(static_cast<std::size_t>(g_), params_.noise.fixed);
    smoother_ = std::make_unique<FixedLagSmoother>(layout_, noise_, params_.fixed_lag, params_.publish_every);
  }
}

FilterCounters FactorStream::counters() const {
  return smoother_ ? smoother_->filter().counters() : FilterCounters{};
}

void FactorStream::feed(const Eigen::Ref<const RowMajorMatrix>& block, bool discontinuity,
                        std::int64_t first_time_ns, double period_ns, std::vector<FactorReport>& out) {
  if (block.cols() != g_) {
    throw std::invalid_argument("block has " + std::to_string(block.cols()) + " channels, the model has " +
                                std::to_string(g_));
  }
  for (Eigen::Index row = 0; row < block.rows(); ++row) {
    const double* y = block.data() + row * block.outerStride();
    const bool disc = discontinuity && row == 0;
    const std::int64_t t = first_time_ns + static_cast<std::int64_t>(std::llround(static_cast<double>(row) * period_ns));
    ++buffered_index_;
    if (smoother_) {
      process(y, disc, t, out);
      continue;
    }
    buffer_.insert(buffer_.end(), y, y + g_);
    buffer_disc_.push_back(disc);
    buffer_time_.push_back(t);
    if (buffer_disc_.size() >= params_.noise.calibration_samples) calibrate(out);
  }
}

void FactorStream::calibrate(std::vector<FactorReport>& out) {
  const auto n = static_cast<Eigen::Index>(buffer_disc_.size());
  const Eigen::MatrixXd samples =
      Eigen::Map<const RowMajorMatrix>(buffer_.data(), n, static_cast<Eigen::Index>(g_));
  NoiseTuningOptions options;
  options.p0 = params_.noise.fixed.p0;
  tuning_ = tune_noise_all(layout_, samples, buffer_disc_, options);
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
  smoother_ = std::make_unique<FixedLagSmoother>(layout_, noise_, params_.fixed_lag, params_.publish_every);
  // Replay the calibration window so no sample is lost.
  for (Eigen::Index i = 0; i < n; ++i) {
    process(buffer_.data() + i * g_, buffer_disc_[static_cast<std::size_t>(i)],
            buffer_time_[static_cast<std::size_t>(i)], out);
  }
  buffer_.clear();
  buffer_disc_.clear();
  buffer_time_.clear();
}

void FactorStream::process(const double* y, bool discontinuity, std::int64_t time_ns, std::vector<FactorReport>& out) {
  std::uint64_t released_index = 0;
  const bool released =
      smoother_->step_into(y, discontinuity, &released_index, all_factors_.data(), all_std_.data());
  if (smoother_->last_status() == SampleStatus::Updated) stats_.add(smoother_->filter());
  const std::uint64_t index = next_index_++;
  if (released && params_.fixed_lag > 0) {
    emit_smoothed(SmoothedSample{released_index, all_factors_, all_std_}, out);
  }
  if (++since_report_ >= params_.publish_every) {
    since_report_ = 0;
    emit_filter(index, time_ns, out);
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

void FactorStream::emit_filter(std::uint64_t index, std::int64_t time_ns, std::vector<FactorReport>& out) {
  const auto& filter = smoother_->filter();
  Eigen::VectorXd factors(all_factors_.size()), stds(all_std_.size());
  filter.estimates(factors.data());
  filter.std_devs(stds.data());
  Pending pending{index, time_ns, {}};
  for (int k = 0; k < g_; ++k) {
    FactorReport r = make_report(EstimateKind::Filter, k, index, time_ns, factors, stds);
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

void FactorStream::emit_smoothed(const SmoothedSample& s, std::vector<FactorReport>& out) {
  // Only the indices that got a filter report get a smoothed twin (same cadence on both topics).
  while (!pending_.empty() && pending_.front().index < s.index) pending_.pop_front();
  if (pending_.empty() || pending_.front().index != s.index) return;
  const Pending& p = pending_.front();
  for (int k = 0; k < g_; ++k) {
    FactorReport r = make_report(EstimateKind::FixedLag, k, s.index, p.time_ns, s.estimates, s.std_devs);
    const FactorReport& twin = p.filter_reports[static_cast<std::size_t>(k)];
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
    if (buffer_disc_.empty()) return;
    calibrate(out);
  }
  for (const SmoothedSample& s : smoother_->flush()) {
    if (params_.fixed_lag > 0) emit_smoothed(s, out);
  }
}

}  // namespace causal::pipeline
