#include "prognosis_scoring.hpp"
#include "prognosis_anchors.hpp"
#include "prognosis_conformal.hpp"
#include "run_to_failure_sim.hpp"
#include "causal/prognosis/excess_growth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace causal::prognosis_eval {

namespace {

constexpr double kNsPerHour = 3.6e12;
constexpr prognosis::Level kAll[kLevels] = {prognosis::Level::warning, prognosis::Level::critical,
                                            prognosis::Level::end_of_life};

double median_of(std::vector<double> v) {
  if (v.empty()) return NAN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

Prediction from(const prognosis::TimeToLevel& t) {
  Prediction p;
  p.known = t.known;
  p.reached = t.reached;
  p.hours = t.hours;
  p.low = t.hours_low;
  p.high = t.hours_high;
  p.why = t.why;
  return p;
}

}  // namespace

std::array<std::int64_t, kLevels> median_crossings(const std::vector<std::int64_t>& time_ns,
                                                   const std::vector<double>& values, double reference,
                                                   std::int64_t from, const std::array<double, kLevels>& ratios,
                                                   std::int64_t stop_index, std::array<std::int64_t, kLevels>* index_out) {
  std::array<std::int64_t, kLevels> truth{0, 0, 0}, index{-1, -1, -1};
  const auto n = static_cast<std::int64_t>(values.size());
  const std::int64_t last = stop_index >= 0 ? std::min(stop_index, n - 1) : n - 1;
  std::vector<double> w;
  for (int l = 0; l < kLevels; ++l) {
    const auto li = static_cast<std::size_t>(l);
    for (std::int64_t i = std::max<std::int64_t>(from, kMedianWindow - 1); i <= last; ++i) {
      w.clear();
      for (std::int64_t j = i - kMedianWindow + 1; j <= i; ++j)
        if (std::isfinite(values[static_cast<std::size_t>(j)])) w.push_back(values[static_cast<std::size_t>(j)]);
      if (w.empty() || median_of(w) < ratios[li] * reference) continue;
      truth[li] = time_ns[static_cast<std::size_t>(i)];
      index[li] = i;
      break;
    }
    if (index[li] < 0 && stop_index >= 0 && stop_index < n) {
      truth[li] = time_ns[static_cast<std::size_t>(stop_index)];
      index[li] = stop_index;
    }
  }
  if (index_out) *index_out = index;
  return truth;
}

const char* method_name(int method) {
  static const char* const names[kMethods] = {"twin", "theil-sen", "rw-drift", "long-run", "conformal"};
  return names[method];
}

void LevelScore::add(const Prediction& p, double actual) {
  ++decisions;
  if (p.reached) ++reached_early;
  if (!p.known) return;
  ++known;
  if (p.low <= actual && actual <= p.high) ++covered;
  if (actual < p.low) ++truth_earlier;
  const double err = std::abs(p.hours - actual);
  if (err <= 0.2 * actual) ++within_20;
  if (err <= 0.3 * actual) ++within_30;
  rel_widths.push_back((p.high - p.low) / actual);
  abs_errors.push_back(err);
}

void LevelScore::merge(const LevelScore& o) {
  decisions += o.decisions;
  known += o.known;
  covered += o.covered;
  reached_early += o.reached_early;
  truth_earlier += o.truth_earlier;
  within_20 += o.within_20;
  within_30 += o.within_30;
  rel_widths.insert(rel_widths.end(), o.rel_widths.begin(), o.rel_widths.end());
  abs_errors.insert(abs_errors.end(), o.abs_errors.begin(), o.abs_errors.end());
}

void MethodScores::merge(const MethodScores& o) {
  for (int l = 0; l < kLevels; ++l) level[static_cast<std::size_t>(l)].merge(o.level[static_cast<std::size_t>(l)]);
}

PrognosisScorer::PrognosisScorer(std::unique_ptr<alarms::AlarmEngine> engine, prognosis::PrognosisParams params,
                                 int channel, std::array<std::int64_t, kLevels> truth_ns)
    : engine_(std::move(engine)),
      trends_(engine_->channel_count(), params),
      channel_(channel),
      truth_ns_(truth_ns) {}

void PrognosisScorer::observe(const alarms::Observation& obs) {
  const auto gaps_before = engine_->discontinuities();
  const auto events = engine_->observe(obs);
  prognosis::observe_for_prognosis(trends_, *engine_, obs,
                                   obs.discontinuity || engine_->discontinuities() > gaps_before);
  const double f = obs.features.size() > channel_ ? obs.features[channel_] : NAN;
  history_.push_back({obs.index, {obs.time_ns, f > 0 ? std::log(f) : NAN}});
  const auto base = prognosis::baselines_of(*engine_);
  for (const auto& e : events) {
    if (first_alarm_index_ < 0 && e.state == alarms::AlarmState::Raised &&
        e.category == alarms::category::kDegradation && e.channel == channel_) {
      first_alarm_index_ = static_cast<std::int64_t>(obs.index);
      onset_index_ = e.onset_index;
      baseline_log_ = base.log_location[channel_];
    }
  }
  if (first_alarm_index_ < 0) return;
  std::array<std::array<Prediction, kLevels>, kMethods> pred{};
  for (const auto& p : prognosis::open_alarm_prognoses(trends_, *engine_, obs.index))
    if (p.channel == channel_) pred[0][static_cast<std::size_t>(p.level)] = from(p.time);
  // Anchors' data: log level over the current baseline since the first alarm's onset, hours from the onset.
  std::vector<double> t, y;
  std::int64_t t0 = 0;
  for (const auto& [index, ty] : history_) {
    if (index < onset_index_ || !std::isfinite(ty.second)) continue;
    if (t.empty()) t0 = ty.first;
    t.push_back(static_cast<double>(ty.first - t0) / kNsPerHour);
    y.push_back(ty.second - base.log_location[channel_]);
  }
  bool any = false;
  for (int l = 0; l < kLevels; ++l) any = any || (truth_ns_[static_cast<std::size_t>(l)] != 0 && obs.time_ns < truth_ns_[static_cast<std::size_t>(l)]);
  if (!any) return;
  const TheilSenBootstrap theil_sen(t, y, 200, 0x5EED0000ULL + obs.index);
  const DriftRandomWalk walk(t, y);
  const ConformalLevel conformal(t, y);
  const double coverage = trends_.params().coverage;
  for (int l = 0; l < kLevels; ++l) {
    const auto i = static_cast<std::size_t>(l);
    if (truth_ns_[i] == 0 || obs.time_ns >= truth_ns_[i]) continue;
    const double actual = static_cast<double>(truth_ns_[i] - obs.time_ns) / kNsPerHour;
    const double log_ratio =
        std::log(trends_.ratio(kAll[l], engine_->params().warning_ratio, engine_->params().critical_ratio));
    pred[1][i] = theil_sen.time_to(log_ratio, coverage);
    pred[2][i] = walk.time_to(log_ratio, coverage);
    pred[3][i] = from(prognosis::excess_growth_time_to(t, y, base.log_scale[channel_], log_ratio, trends_.params()));
    pred[4][i] = conformal.time_to(log_ratio, coverage);
    std::string line = std::to_string(obs.index) + " " + prognosis::to_string(kAll[l]);
    char buf[200];
    std::snprintf(buf, sizeof buf, " actual=%.2f", actual);
    line += buf;
    for (int m = 0; m < kMethods; ++m) {
      const Prediction& p = pred[static_cast<std::size_t>(m)][i];
      scores_[static_cast<std::size_t>(m)].level[i].add(p, actual);
      std::snprintf(buf, sizeof buf, " %s=%s%.2f [%.2f, %.2f]", method_name(m), p.known ? "" : "unknown ", p.hours,
                    p.low, p.high);
      line += buf;
    }
    trace.push_back(line + " " + pred[0][i].why);
  }
}

std::string score_table(const std::string& title, const std::array<MethodScores, kMethods>& scores) {
  std::string out = title + "\n";
  char buf[300];
  std::snprintf(buf, sizeof buf, "| %-11s | %-9s | %9s | %8s | %8s | %10s | %7s | %7s | %13s |\n", "level", "method",
                "decisions", "answered", "coverage", "med rel w", "a-l 20%", "a-l 30%", "truth earlier");
  out += buf;
  out += "|-------------|-----------|-----------|----------|----------|------------|---------|---------|---------------|\n";
  for (int l = 0; l < kLevels; ++l) {
    for (int m = 0; m < kMethods; ++m) {
      const LevelScore& s = scores[static_cast<std::size_t>(m)].level[static_cast<std::size_t>(l)];
      const double d = static_cast<double>(s.decisions), k = static_cast<double>(s.known);
      std::snprintf(buf, sizeof buf, "| %-11s | %-9s | %9llu | %8.2f | %8.2f | %10.2f | %7.2f | %7.2f | %13.2f |\n",
                    prognosis::to_string(kAll[l]), method_name(m), static_cast<unsigned long long>(s.decisions),
                    s.decisions ? k / d : 0.0, s.known ? static_cast<double>(s.covered) / k : 0.0,
                    median_of(s.rel_widths), s.decisions ? static_cast<double>(s.within_20) / d : 0.0,
                    s.decisions ? static_cast<double>(s.within_30) / d : 0.0,
                    s.known ? static_cast<double>(s.truth_earlier) / k : 0.0);
      out += buf;
    }
  }
  return out;
}

namespace {

void feed(PrognosisScorer& s, const SimRun& run) {
  for (std::size_t i = 0; i < run.time_ns.size(); ++i) {
    alarms::Observation obs;
    obs.index = i;
    obs.time_ns = run.time_ns[i];
    obs.discontinuity = run.discontinuity[i];
    obs.features = run.features.row(static_cast<Eigen::Index>(i)).transpose();
    s.observe(obs);
  }
}

std::unique_ptr<alarms::AlarmEngine> sim_engine() {
  return std::make_unique<alarms::AlarmEngine>("sim", std::vector<std::string>{"wearing", "healthy"},
                                               std::vector<std::string>{}, alarms::AlarmParams{});
}

}  // namespace

PrognosisScorer score_simulated_run(const SimRun& run, const prognosis::PrognosisParams& params) {
  // First pass: where the alarm starts and the baseline it judges by; second: scored against its crossings.
  PrognosisScorer first(sim_engine(), params, 0, {0, 0, 0});
  feed(first, run);
  std::array<std::int64_t, kLevels> truth{0, 0, 0};
  if (first.first_alarm_index() >= 0) {
    const alarms::AlarmParams alarm;
    std::vector<double> level(run.time_ns.size());
    for (std::size_t i = 0; i < level.size(); ++i) level[i] = run.features(static_cast<Eigen::Index>(i), 0);
    truth = median_crossings(run.time_ns, level, std::exp(first.baseline_log()), first.first_alarm_index(),
                             {alarm.warning_ratio, alarm.critical_ratio, params.end_of_life_ratio},
                             static_cast<std::int64_t>(run.time_ns.size()) - 1);
  }
  PrognosisScorer s(sim_engine(), params, 0, truth);
  feed(s, run);
  return s;
}

}  // namespace causal::prognosis_eval
