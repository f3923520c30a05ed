#include "causal/estimation/noise_tuning.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "filter_access.hpp"
#include "rts_pass.hpp"

namespace causal::estimation {
namespace {

constexpr double kLog2Pi = 1.8378770664093454836;  // log(2 pi)
constexpr double kSearchTol = 0.01;                // decades of lambda
constexpr double kRoundRTol = 1e-3;                // relative change of r_hat that ends the rounds
constexpr double kRoundLambdaTol = 0.05;           // decades
// r_hat below this fraction of the outcome's mean square means the filter "explains" the window to rounding
// (12 decades: far below any sensor's noise floor relative to its signal): a degenerate, failed candidate.
constexpr double kMinRelativeR = 1e-12;

struct Point {
  double log10_lambda;
  double loglik;  // concentrated
  double r_hat;
};

// Likelihood sums of one filter pass per candidate lane.
struct PassSums {
  std::array<double, detail::kLanes> sum_log_s{};
  std::array<double, detail::kLanes> sum_e2_over_s{};
  std::int64_t updates = 0;
};

// Evaluates up to 4 noise settings of outcome k in one pass of the filter recursion (SvarKalmanFilter with
// outcome k replicated in the 4 SIMD lanes, one candidate per lane).
struct Tuner {
  const SvarLayout& layout;
  int k;
  const Eigen::MatrixXd& samples;
  const std::vector<bool>& discontinuity;
  double mean_square;  // of y_k over the usable samples: the scale a sane r_hat is compared with
  int passes = 0;
  int failed = 0;      // candidates with a non-finite or degenerate likelihood

  Tuner(const SvarLayout& l, int outcome, const Eigen::MatrixXd& s, const std::vector<bool>& disc, double ms)
      : layout(l), k(outcome), samples(s), discontinuity(disc), mean_square(ms) {}

  // `used` lanes carry candidates (the others repeat one to fill the SIMD width): only theirs are summed, which
  // saves the logarithms of the filler lanes (the grid's last pass, the exact pass: 3 of 4).
  PassSums pass(const std::array<NoiseParams, detail::kLanes>& noise, int used) {
    SvarKalmanFilter f =
        detail::FilterAccess::replicated(layout, k, std::vector<NoiseParams>(noise.begin(), noise.end()));
    PassSums sums;
    std::vector<double> row(samples.cols());
    for (Eigen::Index n = 0; n < samples.rows(); ++n) {
      for (Eigen::Index j = 0; j < samples.cols(); ++j) row[j] = samples(n, j);
      if (f.step(row.data(), !discontinuity.empty() && discontinuity[n]) != SampleStatus::Updated) continue;
      ++sums.updates;
      for (int w = 0; w < used; ++w) {
        const double s = detail::FilterAccess::lane_s(f, 0, w), e = detail::FilterAccess::lane_e(f, 0, w);
        sums.sum_log_s[w] += std::log(s);
        sums.sum_e2_over_s[w] += e * e / s;
      }
    }
    ++passes;
    return sums;
  }

  // Concentrated log-likelihood at each log10(lambda) with P0 = pi r I, filter run in units of r (R = 1).
  std::vector<Point> concentrated(const std::vector<double>& log10_lambdas, double pi) {
    std::vector<Point> out;
    for (std::size_t first = 0; first < log10_lambdas.size(); first += detail::kLanes) {
      std::array<NoiseParams, detail::kLanes> noise;
      const std::size_t m = std::min<std::size_t>(detail::kLanes, log10_lambdas.size() - first);
      for (std::size_t w = 0; w < detail::kLanes; ++w) {
        const double l10 = log10_lambdas[first + std::min(w, m - 1)];
        noise[w] = NoiseParams{std::pow(10.0, l10), 1.0, pi};
      }
      const PassSums job = pass(noise, static_cast<int>(m));
      const auto n = static_cast<double>(job.updates);
      for (std::size_t w = 0; w < m; ++w) {
        const double r_hat = job.sum_e2_over_s[w] / n;
        double ll = -0.5 * (n * (kLog2Pi + std::log(r_hat)) + job.sum_log_s[w] + n);
        // A candidate whose filter lost precision (NaN / inf sums) or explains the window exactly (r_hat
        // vanishing next to the data's mean square: the likelihood is unbounded, not informative) FAILED: it
        // must never win the comparison, whatever NaN ordering would do.
        if (!std::isfinite(ll) || !std::isfinite(r_hat) || !(r_hat > kMinRelativeR * mean_square)) {
          ll = -std::numeric_limits<double>::infinity();
          ++failed;
        }
        out.push_back({log10_lambdas[first + w], ll, r_hat});
      }
    }
    return out;
  }

  double exact(const NoiseParams& noise, long* updates) {
    std::array<NoiseParams, detail::kLanes> lanes;
    lanes.fill(noise);
    const PassSums job = pass(lanes, 1);
    if (updates) *updates = static_cast<long>(job.updates);
    if (job.updates == 0) return -std::numeric_limits<double>::infinity();
    return -0.5 * (static_cast<double>(job.updates) * kLog2Pi + job.sum_log_s[0] + job.sum_e2_over_s[0]);
  }
};

// Sum of y_k^2 over the samples that update the filter (status Updated), and their number `n`.
double updated_sum_of_squares(const Eigen::MatrixXd& samples, int k, const std::vector<SampleStatus>& status,
                              long& n) {
  double sum_sq = 0.0;
  n = 0;
  for (Eigen::Index i = 0; i < samples.rows(); ++i) {
    if (status[i] != SampleStatus::Updated) continue;
    sum_sq += samples(i, k) * samples(i, k);
    ++n;
  }
  return sum_sq;
}

// Outcome without factors: y_k = eps, the likelihood depends on r only (r_hat = mean y_k^2), q is moot.
double empty_outcome_loglik(const Eigen::MatrixXd& samples, int k, const std::vector<SampleStatus>& status,
                            double r, long* updates) {
  long n = 0;
  const double sum_sq = updated_sum_of_squares(samples, k, status, n);
  if (updates) *updates = n;
  if (n == 0) return -std::numeric_limits<double>::infinity();
  return -0.5 * (static_cast<double>(n) * (kLog2Pi + std::log(r)) + sum_sq / r);
}

void check_outcome(const SvarLayout& layout, int k, const char* what) {
  if (k < 0 || k >= layout.channels()) {
    throw std::invalid_argument(std::string(what) + ": outcome " + std::to_string(k) + " out of range [0, " +
                                std::to_string(layout.channels()) + ")");
  }
}

}  // namespace

double innovation_log_likelihood(const SvarLayout& layout, int k, const Eigen::MatrixXd& samples,
                                 const std::vector<bool>& discontinuity, const NoiseParams& noise,
                                 long* updates) {
  validate_noise_params(noise, "noise");
  check_outcome(layout, k, "innovation_log_likelihood");
  const std::vector<SampleStatus> status = detail::classify_all(layout, samples, discontinuity);
  if (layout.factor_count(k) == 0) return empty_outcome_loglik(samples, k, status, noise.r, updates);
  Tuner t(layout, k, samples, discontinuity, 0.0);
  return t.exact(noise, updates);
}

namespace {

void validate_tuning_options(const NoiseTuningOptions& options) {
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
}

// Initial r reference: mean square of y_k over the usable samples (an upper bound on r for zero factors).
// Returns false, with result.message saying why, when outcome k cannot be tuned (too few samples, absurd or
// dead channel) or needs no search (no factors: r = mean square of y, result complete).
bool reference_r(const SvarLayout& layout, int k, const Eigen::MatrixXd& samples,
                 const std::vector<SampleStatus>& status, NoiseTuningResult& result, double& r_ref) {
  long usable = 0;
  const double sum_sq = updated_sum_of_squares(samples, k, status, usable);
  result.updates = usable;
  const int d = layout.factor_count(k);
  if (usable < 2 * d + 10) {
    result.message = "too few usable samples for outcome " + std::to_string(k + 1) + ": " +
                     std::to_string(usable) + " < " + std::to_string(2 * d + 10) + "; default noise kept";
    return false;
  }
  r_ref = sum_sq / static_cast<double>(usable);
  if (!std::isfinite(r_ref)) {
    result.message = "outcome " + std::to_string(k + 1) + ": the mean square of y over the window is not finite "
                     "(absurd values in the window); not tuned, use configured noise";
    return false;
  }
  if (!(r_ref > 0.0)) {
    result.message = "outcome " + std::to_string(k + 1) + " is identically zero over the window (dead channel?); "
                     "not tuned, use configured noise";
    return false;
  }
  if (d == 0) {
    result.noise.r = r_ref;
    result.noise.q = 0.0;
    result.log_likelihood = empty_outcome_loglik(samples, k, status, r_ref, nullptr);
    result.converged = true;
    result.usable = std::isfinite(result.log_likelihood);
    result.message = "outcome " + std::to_string(k + 1) + " has no factors: r = mean square of y";
    return false;
  }
  return true;
}

struct SearchOutcome {
  Point best;
  bool search_done = false;  // the last bracket shrank below kSearchTol
  bool rounds_done = false;  // r_hat and lambda stopped moving between rounds
};

// Maximises the concentrated likelihood over log10(q/r) in rounds: each round re-centres r on the previous
// round's r_hat (the concentrated likelihood is exact only at the r it was concentrated at).
SearchOutcome search_ratio(Tuner& t, const NoiseTuningOptions& options, double r_ref) {
  const int budget = options.max_evaluations - 1;  // keep one pass for the exact final likelihood
  const double lo = options.log10_ratio_min, hi = options.log10_ratio_max;
  SearchOutcome out;
  // Round 1 starts from a coarse 1-decade grid.
  double pi = options.p0 / r_ref;
  std::vector<double> grid;
  for (double v = lo; v < hi + 0.5; v += 1.0) grid.push_back(std::min(v, hi));
  out.best = Point{lo, -std::numeric_limits<double>::infinity(), r_ref};
  for (const Point& p : t.concentrated(grid, pi)) {
    if (p.loglik > out.best.loglik) out.best = p;
  }
  double half = 1.0;
  for (int round = 0; t.passes < budget; ++round) {
    const double center = out.best.log10_lambda;
    // 4-point search: each pass evaluates 4 equally spaced interior points of [a, b] (one per lane) and
    // shrinks the bracket to +-1 spacing around the best point seen (for a unimodal likelihood the maximum
    // lies within one spacing of the best sample): width x 0.4 per pass.
    double a = std::max(lo, center - half), b = std::min(hi, center + half);
    Point round_best{center, -std::numeric_limits<double>::infinity(), r_ref};
    out.search_done = false;
    while (t.passes < budget) {
      if (b - a < kSearchTol) {
        out.search_done = true;
        break;
      }
      const double step = (b - a) / 5.0;
      std::vector<double> pts;
      for (int i = 1; i <= 4; ++i) pts.push_back(a + step * i);
      for (const Point& p : t.concentrated(pts, pi)) {
        if (p.loglik > round_best.loglik) round_best = p;
      }
      a = std::max(a, round_best.log10_lambda - step);
      b = std::min(b, round_best.log10_lambda + step);
    }
    if (b - a < kSearchTol) out.search_done = true;
    if (!std::isfinite(round_best.loglik)) break;  // every candidate of this round failed: keep the last good one
    const double r_change = std::abs(round_best.r_hat / r_ref - 1.0);
    const double lambda_change = std::abs(round_best.log10_lambda - center);
    out.best = round_best;
    r_ref = round_best.r_hat;
    pi = options.p0 / r_ref;
    half = 0.5;
    if (round > 0 && out.search_done && r_change < kRoundRTol && lambda_change < kRoundLambdaTol) {
      out.rounds_done = true;
      break;
    }
  }
  return out;
}

std::string tuning_message(int k, const NoiseTuningResult& result, const NoiseTuningOptions& options,
                           double log10_lambda, int failed) {
  const double lo = options.log10_ratio_min, hi = options.log10_ratio_max;
  std::ostringstream os;
  os << "outcome " << (k + 1) << ": q = " << result.noise.q << ", r = " << result.noise.r
     << ", log10(q/r) = " << log10_lambda << ", log-likelihood = " << result.log_likelihood << " over "
     << result.updates << " samples, " << result.evaluations << " filter passes";
  if (!result.converged) os << "; NOT converged within max_evaluations = " << options.max_evaluations;
  if (result.at_range_limit) {
    os << "; optimum at the " << (log10_lambda - lo < 0.05 ? "lower" : "upper")
       << " limit of the log10(q/r) range [" << lo << ", " << hi << "]";
  }
  if (failed > 0) os << "; " << failed << " candidates failed (non-finite likelihood)";
  if (!result.usable) os << "; NOT usable (non-finite q, r or likelihood): not tuned, use configured noise";
  return os.str();
}

}  // namespace

NoiseTuningResult tune_noise(const SvarLayout& layout, int k, const Eigen::MatrixXd& samples,
                             const std::vector<bool>& discontinuity, const NoiseTuningOptions& options) {
  check_outcome(layout, k, "tune_noise");
  validate_tuning_options(options);
  const std::vector<SampleStatus> status = detail::classify_all(layout, samples, discontinuity);
  NoiseTuningResult result;
  result.noise.p0 = options.p0;
  double r_ref = 0.0;
  if (!reference_r(layout, k, samples, status, result, r_ref)) return result;

  Tuner t(layout, k, samples, discontinuity, r_ref);
  const SearchOutcome found = search_ratio(t, options, r_ref);
  const Point& best = found.best;
  result.evaluations = t.passes;
  result.failed_candidates = t.failed;
  if (!std::isfinite(best.loglik)) {
    result.message = "outcome " + std::to_string(k + 1) + ": no candidate q/r gave a finite likelihood (" +
                     std::to_string(t.failed) + " failed); not tuned, use configured noise";
    return result;
  }
  result.noise.r = best.r_hat;
  result.noise.q = std::pow(10.0, best.log10_lambda) * best.r_hat;
  result.noise.p0 = options.p0;
  result.log_likelihood = t.exact(result.noise, nullptr);
  result.evaluations = t.passes;
  result.usable = std::isfinite(result.noise.q) && result.noise.q >= 0.0 && std::isfinite(result.noise.r) &&
                  result.noise.r > 0.0 && std::isfinite(result.log_likelihood);
  result.converged = found.search_done && found.rounds_done;
  result.at_range_limit =
      best.log10_lambda - options.log10_ratio_min < 0.05 || options.log10_ratio_max - best.log10_lambda < 0.05;
  result.message = tuning_message(k, result, options, best.log10_lambda, t.failed);
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

}  // namespace causal::estimation
