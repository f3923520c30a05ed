#include "causal/alarms/alarm_params.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "causal/alarms/statistics.hpp"

namespace causal::alarms {

namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("AlarmParams: " + what);
}
bool prob_ok(double p) { return p > 0.0 && p < 0.5; }
}  // namespace

void AlarmParams::validate() const {
  require(warmup_observations >= 0, "warmup_observations must be >= 0");
  require(baseline_observations >= 8, "baseline_observations must be >= 8 (median/MAD need a sample)");
  require(min_baseline_coverage > 0.0 && min_baseline_coverage <= 1.0, "min_baseline_coverage must be in (0, 1]");
  require(baseline_confidence >= 0.5 && baseline_confidence < 1.0, "baseline_confidence must be in [0.5, 1)");
  require(std::isfinite(cusum_k) && cusum_k > 0.0, "cusum_k must be > 0");
  require(std::isfinite(target_arl0) && target_arl0 > 10.0, "target_arl0 must be > 10 observations");
  require(std::isfinite(clip_sigma) && clip_sigma > cusum_k, "clip_sigma must be > cusum_k");
  require(std::isfinite(cusum_cap_factor) && cusum_cap_factor >= 1.0, "cusum_cap_factor must be >= 1");
  require(clear_fraction > 0.0 && clear_fraction <= 1.0, "clear_fraction must be in (0, 1]");
  require(raise_persistence >= 1, "raise_persistence must be >= 1");
  require(clear_persistence >= 1, "clear_persistence must be >= 1");
  require(level_window >= 1, "level_window must be >= 1");
  require(warning_ratio > 1.0 && critical_ratio > warning_ratio, "need 1 < warning_ratio < critical_ratio");
  require(stopped_ratio >= 0.0 && stopped_ratio < 1.0, "stopped_ratio must be in [0, 1)");
  require(warning_sigma > 0.0 && critical_sigma > warning_sigma, "need 0 < warning_sigma < critical_sigma");
  require(nis_window >= 2, "nis_window must be >= 2");
  require(prob_ok(nis_false_alarm_prob), "nis_false_alarm_prob must be in (0, 0.5)");
  require(prob_ok(factor_false_alarm_prob), "factor_false_alarm_prob must be in (0, 0.5)");
  require(factor_persistence >= 1, "factor_persistence must be >= 1");
  require(onset_tolerance >= 0, "onset_tolerance must be >= 0");
  require(std::isfinite(own_evidence_z) && own_evidence_z > 0.0, "own_evidence_z must be > 0");
  require(explain_top_factors >= 0, "explain_top_factors must be >= 0");
  const double h = cusum_threshold();
  // The one-spike guarantee: with raise_persistence 1, a single clipped observation (clip - k) must not
  // reach h on its own.
  require(raise_persistence >= 2 || clip_sigma - cusum_k < h,
          "clip_sigma - cusum_k (" + std::to_string(clip_sigma - cusum_k) + ") must be < the CUSUM threshold h (" +
              std::to_string(h) + ") when raise_persistence is 1, otherwise one spike could raise an alarm");
  // Same promise for the NIS window: one clipped value (clip^2) spread over the window must stay below
  // the window threshold.
  require(raise_persistence >= 2 || clip_sigma * clip_sigma / nis_window < nis_threshold(),
          "clip_sigma^2 / nis_window must be < the NIS threshold when raise_persistence is 1");
}

double AlarmParams::cusum_threshold() const { return cusum_threshold_for_arl0(cusum_k, target_arl0); }

double AlarmParams::nis_threshold() const {
  // Under H0 the window sum of z^2 is chi-square(nis_window); clipping at clip^2 only lowers it, so the
  // false-alarm probability is at most nis_false_alarm_prob per observation.
  return chi_square_upper_quantile(nis_window, nis_false_alarm_prob) / nis_window;
}

double AlarmParams::factor_threshold(int factor_count) const {
  const int n = std::max(1, factor_count);
  return normal_upper_quantile(factor_false_alarm_prob / (2.0 * n));
}

AlarmParams AlarmParams::sample_level(int baseline_publications) {
  AlarmParams p;
  p.warmup_observations = 1;
  p.baseline_observations = baseline_publications - p.warmup_observations;
  p.factor_enabled = false;
  // A 1-s snapshot gives ~20 publications of 1024 samples: a window of 4 stays within one snapshot.
  p.nis_window = 4;
  p.validate();
  return p;
}

}  // namespace causal::alarms
