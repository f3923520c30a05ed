#include "causal/alarms/alarm_params.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "causal/alarms/statistics.hpp"
#include "causal/estimation/state_archive.hpp"

namespace causal::alarms {

namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("AlarmParams: " + what);
}
bool prob_ok(double p) { return p > 0.0 && p < 0.5; }

// Every field of AlarmParams with its name (P = AlarmParams or const AlarmParams). Checkpoints and the
// comparison of a checkpoint's parameters with the configured ones go through this one list.
template <typename P, typename F>
void for_each_param(P& p, F&& f) {
  f("warmup_observations", p.warmup_observations);
  f("baseline_observations", p.baseline_observations);
  f("min_baseline_coverage", p.min_baseline_coverage);
  f("baseline_confidence", p.baseline_confidence);
  f("cusum_k", p.cusum_k);
  f("target_arl0", p.target_arl0);
  f("clip_sigma", p.clip_sigma);
  f("cusum_cap_factor", p.cusum_cap_factor);
  f("clear_fraction", p.clear_fraction);
  f("raise_persistence", p.raise_persistence);
  f("innovation_persistence", p.innovation_persistence);
  f("clear_persistence", p.clear_persistence);
  f("level_window", p.level_window);
  f("feature_enabled", p.feature_enabled);
  f("feature_log_transform", p.feature_log_transform);
  f("warning_ratio", p.warning_ratio);
  f("critical_ratio", p.critical_ratio);
  f("advisory_ratio", p.advisory_ratio);
  f("baseline_tracking_observations", p.baseline_tracking_observations);
  f("healthy_range_observations", p.healthy_range_observations);
  f("max_absorbed_ratio", p.max_absorbed_ratio);
  f("stopped_ratio", p.stopped_ratio);
  f("innovation_enabled", p.innovation_enabled);
  f("nis_enabled", p.nis_enabled);
  f("nis_two_sided", p.nis_two_sided);
  f("nis_window", p.nis_window);
  f("nis_false_alarm_prob", p.nis_false_alarm_prob);
  f("warning_sigma", p.warning_sigma);
  f("critical_sigma", p.critical_sigma);
  f("factor_enabled", p.factor_enabled);
  f("factor_false_alarm_prob", p.factor_false_alarm_prob);
  f("factor_persistence", p.factor_persistence);
  f("onset_tolerance", p.onset_tolerance);
  f("own_evidence_z", p.own_evidence_z);
  f("explain_top_factors", p.explain_top_factors);
  f("confirmation_observations", p.confirmation_observations);
  f("gap_multiple", p.gap_multiple);
  f("operating_step_ratio", p.operating_step_ratio);
  f("settle_trend_sigma", p.settle_trend_sigma);
  f("escalation_persistence", p.escalation_persistence);
  f("root_cause_margin_z", p.root_cause_margin_z);
  f("root_cause_persistence", p.root_cause_persistence);
}
constexpr std::uint32_t kParamCount = 42;
// Tripwire (x86-64 layout): a field added to AlarmParams usually changes its size. List it in
// for_each_param (or checkpoints would ignore it), bump kParamCount, then update this size.
static_assert(sizeof(void*) != 8 || sizeof(AlarmParams) == 256,
              "AlarmParams changed: update for_each_param and kParamCount");

}  // namespace

void save(estimation::StateWriter& out, const AlarmParams& params) {
  out.begin("alarm_params", 1);
  out.put(kParamCount);
  for_each_param(params, [&](const char* name, const auto& value) {
    out.put(name);
    out.put(value);
  });
}

void restore(estimation::StateReader& in, AlarmParams& params) {
  in.expect("alarm_params", 1);
  const auto count = in.get<std::uint32_t>();
  if (count != kParamCount) {
    throw estimation::StateError("checkpoint: " + std::to_string(count) + " alarm parameters saved, this build has " +
                             std::to_string(kParamCount));
  }
  AlarmParams p;
  for_each_param(p, [&](const char* name, auto& value) {
    const auto saved = in.get<std::string>();
    if (saved != name) {
      throw estimation::StateError("checkpoint: alarm parameter '" + saved + "' where this build expects '" + name + "'");
    }
    in.read(value);
  });
  params = p;
}

std::string param_differences(const AlarmParams& a, const AlarmParams& b) {
  // Printed with 17 significant digits, two doubles print the same only when they are equal.
  auto printed = [](const AlarmParams& p) {
    std::vector<std::pair<std::string, std::string>> out;
    for_each_param(p, [&](const char* name, const auto& value) {
      std::ostringstream os;
      os.precision(17);
      os << std::boolalpha << value;
      out.emplace_back(name, os.str());
    });
    return out;
  };
  const auto pa = printed(a), pb = printed(b);
  std::string diff;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    if (pa[i].second == pb[i].second) continue;
    diff += (diff.empty() ? "" : ", ") + pa[i].first + ": " + pa[i].second + " -> " + pb[i].second;
  }
  return diff;
}

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
  require(innovation_persistence >= 1, "innovation_persistence must be >= 1");
  require(clear_persistence >= 1, "clear_persistence must be >= 1");
  require(level_window >= 1, "level_window must be >= 1");
  require(warning_ratio > 1.0 && critical_ratio > warning_ratio, "need 1 < warning_ratio < critical_ratio");
  require(std::isfinite(advisory_ratio) && advisory_ratio >= 1.0 && advisory_ratio < warning_ratio,
          "need 1 <= advisory_ratio < warning_ratio");
  require(healthy_range_observations >= 0, "healthy_range_observations must be >= 0");
  require(baseline_tracking_observations >= 0, "baseline_tracking_observations must be >= 0 (0 = no tracking)");
  require(std::isfinite(max_absorbed_ratio) && max_absorbed_ratio >= 1.0 && max_absorbed_ratio < warning_ratio,
          "need 1 <= max_absorbed_ratio < warning_ratio");
  require(stopped_ratio >= 0.0 && stopped_ratio < 1.0, "stopped_ratio must be in [0, 1)");
  require(warning_sigma > 0.0 && critical_sigma > warning_sigma, "need 0 < warning_sigma < critical_sigma");
  require(nis_window >= 2, "nis_window must be >= 2");
  require(prob_ok(nis_false_alarm_prob), "nis_false_alarm_prob must be in (0, 0.5)");
  require(prob_ok(factor_false_alarm_prob), "factor_false_alarm_prob must be in (0, 0.5)");
  require(factor_persistence >= 1, "factor_persistence must be >= 1");
  require(onset_tolerance >= 0, "onset_tolerance must be >= 0");
  require(std::isfinite(own_evidence_z) && own_evidence_z > 0.0, "own_evidence_z must be > 0");
  require(explain_top_factors >= 0, "explain_top_factors must be >= 0");
  require(confirmation_observations >= 3, "confirmation_observations must be >= 3 (a slope needs a window)");
  require(std::isfinite(gap_multiple) && gap_multiple > 1.0, "gap_multiple must be > 1");
  require(std::isfinite(operating_step_ratio) && operating_step_ratio > 1.0, "operating_step_ratio must be > 1");
  require(std::isfinite(settle_trend_sigma) && settle_trend_sigma > 0.0, "settle_trend_sigma must be > 0");
  require(escalation_persistence >= 1, "escalation_persistence must be >= 1");
  require(std::isfinite(root_cause_margin_z) && root_cause_margin_z > 0.0, "root_cause_margin_z must be > 0");
  require(root_cause_persistence >= 1, "root_cause_persistence must be >= 1");
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
  // Publications come in bursts (a 1-s snapshot every 10 min gives ~20 publications 50 ms apart): the
  // pause between bursts is the acquisition pattern, not a gap in the machine's history. Gaps and
  // operating changes are judged at the condition level (one observation per snapshot).
  p.gap_multiple = 1e15;
  p.validate();
  return p;
}

}  // namespace causal::alarms
