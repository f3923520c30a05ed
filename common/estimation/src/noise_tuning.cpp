#include "causal/noise_tuning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "outcome_pass.hpp"

namespace causal {
namespace {

constexpr double kLog2Pi = 1.8378770664093454836;  // log(2 pi)
constexpr double kGoldenTol = 0.01;               // decades of lambda
constexpr double kRoundRTol = 1e-3;               // relative change of r_hat that ends the rounds
constexpr double kRoundLambdaTol = 0.05;          // decades

struct Tuner {
  const SvarLayout& layout;
  int k;
  const Eigen::MatrixXd& samples;
  const std::vector<SampleStatus>& status;
  int evaluations = 0;

  // One filter pass with (q, r, p0); returns the sums of the likelihood.
  detail::OutcomeForward pass(const NoiseParams& noise) {
    detail::OutcomeForward job;
    job.layout = &layout;
    job.k = k;
    job.samples = &samples;
    job.status = &status;
    job.noise = noise;
    detail::run_outcome_forward(job);
    ++evaluations;
    return job;
  }

  struct Point {
    double log10_lambda;
    double loglik;  // concentrated
    double r_hat;
  };

  // Concentrated log-likelihood at lambda with P0 = pi r I, filter run in units of r (R = 1).
  Point concentrated(double log10_lambda, double pi) {
    const double lambda = std::pow(10.0, log10_lambda);
    const detail::OutcomeForward job = pass({lambda, 1.0, pi});
    const auto n = static_cast<double>(job.updates);
    const double r_hat = std::max(job.sum_e2_over_s / n, std::numeric_limits<double>::min());
    const double ll = -0.5 * (n * (kLog2Pi + std::log(r_hat)) + job.sum_log_s + n);
    return {log10_lambda, ll, r_hat};
  }
};

}  // namespace

double innovation_log_likelihood(const SvarLayout& layout, int k, const Eigen::MatrixXd& samples,
                                 const std::vector<bool>& discontinuity, const NoiseParams& noise,
                                 long* updates) {
  validate_noise_params(noise, "noise");
  if (k < 0 || k >= layout.channels()) throw std::invalid_argument("outcome index out of range");
  const std::vector<SampleStatus> status = detail::classify_all(layout, samples, discontinuity);
  Tuner t{layout, k, samples, status};
  const detail::OutcomeForward job = t.pass(noise);
  if (updates) *updates = static_cast<long>(job.updates);
  if (job.updates == 0) return -std::numeric_limits<double>::infinity();
  return -0.5 * (static_cast<double>(job.updates) * kLog2Pi + job.sum_log_s + job.sum_e2_over_s);
}

NoiseTuningResult tune_noise(const SvarLayout& layout, int k, const Eigen::MatrixXd& samples,
                             const std::vector<bool>& discontinuity, const NoiseTuningOptions& options) {
  if (k < 0 || k >= layout.channels()) {
    throw std::invalid_argument("tune_noise: outcome " + std::to_string(k) + " out of range [0, " +
                                std::to_string(layout.channels()) + ")");
  }
  if (!(options.log10_ratio_min < options.log10_ratio_max) || !std::isfinite(options.log10_ratio_min) ||
      !std::isfinite(options.log10_ratio_max)) {
    throw std::invalid_argument("NoiseTuningOptions: need finite log10_ratio_min < log10_ratio_max");
  }
  if (!(options.p0 > 0.0) || !std::isfinite(options.p0)) {
    throw std::invalid_argument("NoiseTuningOptions.p0 must be finite and > 0");
  }
  if (options.max_evaluations < 8) {
    throw std::invalid_argument("NoiseTuningOptions.max_evaluations must be >= 8");
  }
  const std::vector<SampleStatus> status = detail::classify_all(layout, samples, discontinuity);
  NoiseTuningResult result;
  result.noise.p0 = options.p0;

  // Initial r reference: mean square of y_k over the usable samples (an upper bound on r for zero factors).
  double sum_sq = 0.0;
  long usable = 0;
  for (Eigen::Index n = 0; n < samples.rows(); ++n) {
    if (status[n] != SampleStatus::Updated) continue;
    sum_sq += samples(n, k) * samples(n, k);
    ++usable;
  }
  result.updates = usable;
  const int d = layout.factor_count(k);
  if (usable < 2 * d + 10) {
    result.message = "too few usable samples for outcome " + std::to_string(k + 1) + ": " +
                     std::to_string(usable) + " < " + std::to_string(2 * d + 10) + "; default noise kept";
    return result;
  }
  double r_ref = sum_sq / static_cast<double>(usable);
  if (!(r_ref > 0.0)) r_ref = 1.0;

  Tuner t{layout, k, samples, status};
  const int budget = options.max_evaluations - 1;  // keep one pass for the exact final likelihood
  const double lo = options.log10_ratio_min, hi = options.log10_ratio_max;

  // Round 1: coarse 1-decade grid.
  double pi = options.p0 / r_ref;
  Tuner::Point best{lo, -std::numeric_limits<double>::infinity(), r_ref};
  const int grid = static_cast<int>(std::ceil(hi - lo)) + 1;
  for (int i = 0; i < grid && t.evaluations < budget; ++i) {
    const Tuner::Point p = t.concentrated(std::min(lo + i, hi), pi);
    if (p.loglik > best.loglik) best = p;
  }

  bool golden_done = false;
  bool rounds_done = false;
  double half = 1.0;
  for (int round = 0; t.evaluations < budget; ++round) {
    const double center = best.log10_lambda;
    double a = std::max(lo, center - half), b = std::min(hi, center + half);
    // Golden-section search for the maximum of the concentrated likelihood on [a, b].
    constexpr double kInvPhi = 0.6180339887498949;
    double c = b - kInvPhi * (b - a), e = a + kInvPhi * (b - a);
    if (t.evaluations + 2 > budget) break;
    Tuner::Point pc = t.concentrated(c, pi), pe = t.concentrated(e, pi);
    golden_done = false;
    while (t.evaluations < budget) {
      if (b - a < kGoldenTol) {
        golden_done = true;
        break;
      }
      if (pc.loglik >= pe.loglik) {
        b = e;
        e = c;
        pe = pc;
        c = b - kInvPhi * (b - a);
        pc = t.concentrated(c, pi);
      } else {
        a = c;
        c = e;
        pc = pe;
        e = a + kInvPhi * (b - a);
        pe = t.concentrated(e, pi);
      }
    }
    if (b - a < kGoldenTol) golden_done = true;
    const Tuner::Point round_best = pc.loglik >= pe.loglik ? pc : pe;
    const double r_change = std::abs(round_best.r_hat / r_ref - 1.0);
    const double lambda_change = std::abs(round_best.log10_lambda - center);
    best = round_best;
    r_ref = round_best.r_hat;
    pi = options.p0 / r_ref;
    half = 0.5;
    if (round > 0 && golden_done && r_change < kRoundRTol && lambda_change < kRoundLambdaTol) {
      rounds_done = true;
      break;
    }
  }

  const double lambda = std::pow(10.0, best.log10_lambda);
  result.noise.r = best.r_hat;
  result.noise.q = lambda * best.r_hat;
  result.noise.p0 = options.p0;
  {
    const detail::OutcomeForward job = t.pass(result.noise);
    result.log_likelihood =
        -0.5 * (static_cast<double>(job.updates) * kLog2Pi + job.sum_log_s + job.sum_e2_over_s);
  }
  result.evaluations = t.evaluations;
  result.converged = golden_done && rounds_done;
  result.at_range_limit = best.log10_lambda - lo < 0.05 || hi - best.log10_lambda < 0.05;

  std::ostringstream os;
  os << "outcome " << (k + 1) << ": q = " << result.noise.q << ", r = " << result.noise.r
     << ", log10(q/r) = " << best.log10_lambda << ", log-likelihood = " << result.log_likelihood << " over "
     << usable << " samples, " << result.evaluations << " filter passes";
  if (!result.converged) os << "; NOT converged within max_evaluations = " << options.max_evaluations;
  if (result.at_range_limit) {
    os << "; optimum at the " << (best.log10_lambda - lo < 0.05 ? "lower" : "upper")
       << " limit of the log10(q/r) range [" << lo << ", " << hi << "]";
  }
  result.message = os.str();
  return result;
}

std::vector<NoiseTuningResult> tune_noise_all(const SvarLayout& layout, const Eigen::MatrixXd& samples,
                                              const std::vector<bool>& discontinuity,
                                              const NoiseTuningOptions& options) {
  std::vector<NoiseTuningResult> out;
  out.reserve(layout.channels());
  for (int k = 0; k < layout.channels(); ++k) {
    out.push_back(tune_noise(layout, k, samples, discontinuity, options));
  }
  return out;
}

}  // namespace causal
