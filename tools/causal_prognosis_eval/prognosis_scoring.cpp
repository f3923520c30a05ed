#include "prognosis_scoring.hpp"
#include "run_to_failure_sim.hpp"

#include "causal/estimation/normal_quantile.hpp"

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

double kth(std::vector<double>& v, std::size_t k) {
  k = std::min(k, v.size() - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
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

Prediction theil_sen_time_to(const std::vector<double>& t, const std::vector<double>& y, double log_ratio,
                             double coverage) {
  Prediction p;
  const std::size_t n = t.size();
  if (n < 3) return p;
  std::vector<double> slopes;
  slopes.reserve(n * (n - 1) / 2);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      if (t[j] > t[i]) slopes.push_back((y[j] - y[i]) / (t[j] - t[i]));
  if (slopes.size() < 3) return p;
  const double slope = median_of(slopes);
  std::vector<double> resid(n);
  for (std::size_t i = 0; i < n; ++i) resid[i] = y[i] - slope * t[i];
  const double now = median_of(resid) + slope * t.back();
  if (now >= log_ratio) {
    p.known = p.reached = true;
    return p;
  }
  // Sen (1968): ranks (N -+ C) / 2 of the sorted pairwise slopes, C = z sqrt(Var S), Var S = n(n-1)(2n+5)/18.
  const double nn = static_cast<double>(n);
  const double c = causal::normal_quantile(0.5 + 0.5 * coverage) * std::sqrt(nn * (nn - 1) * (2 * nn + 5) / 18.0);
  const double big_n = static_cast<double>(slopes.size());
  const auto lo_rank = static_cast<std::size_t>(std::max(0.0, std::floor((big_n - c) / 2.0) - 1.0));
  const auto hi_rank = static_cast<std::size_t>(std::max(0.0, std::ceil((big_n + c) / 2.0) - 1.0));
  const double slope_lo = kth(slopes, lo_rank), slope_hi = kth(slopes, hi_rank);
  if (slope <= 0 || slope_lo <= 0) return p;  // not rising, or the interval includes "never"
  const double gap = log_ratio - now;
  p.known = true;
  p.hours = gap / slope;
  p.low = gap / slope_hi;
  p.high = gap / slope_lo;
  return p;
}

void LevelScore::add(const Prediction& p, double actual) {
  ++decisions;
  if (p.reached) ++reached_early;
  if (!p.known) return;
  ++known;
  if (p.low <= actual && actual <= p.high) ++covered;
  if (actual < p.low) ++truth_earlier;
  widths.push_back(p.high - p.low);
  abs_errors.push_back(std::abs(p.hours - actual));
}

void LevelScore::merge(const LevelScore& o) {
  decisions += o.decisions;
  known += o.known;
  covered += o.covered;
  reached_early += o.reached_early;
  truth_earlier += o.truth_earlier;
  widths.insert(widths.end(), o.widths.begin(), o.widths.end());
  abs_errors.insert(abs_errors.end(), o.abs_errors.begin(), o.abs_errors.end());
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
  std::array<Prediction, kLevels> twin{}, ts{};
  for (const auto& p : prognosis::open_alarm_prognoses(trends_, *engine_, obs.index))
    if (p.channel == channel_) twin[static_cast<std::size_t>(p.level)] = from(p.time);
  // Baseline data: log level over the current baseline since the first alarm's onset, hours from the onset.
  std::vector<double> t, y;
  std::int64_t t0 = 0;
  for (const auto& [index, ty] : history_) {
    if (index < onset_index_ || !std::isfinite(ty.second)) continue;
    if (t.empty()) t0 = ty.first;
    t.push_back(static_cast<double>(ty.first - t0) / kNsPerHour);
    y.push_back(ty.second - base.log_location[channel_]);
  }
  for (int l = 0; l < kLevels; ++l) {
    const auto i = static_cast<std::size_t>(l);
    if (truth_ns_[i] == 0 || obs.time_ns >= truth_ns_[i]) continue;
    const double actual = static_cast<double>(truth_ns_[i] - obs.time_ns) / kNsPerHour;
    const double ratio = trends_.ratio(kAll[l], engine_->params().warning_ratio, engine_->params().critical_ratio);
    ts[i] = theil_sen_time_to(t, y, std::log(ratio), trends_.params().coverage);
    twin_.level[i].add(twin[i], actual);
    baseline_.level[i].add(ts[i], actual);
    char line[500];
    std::snprintf(line, sizeof line, "%llu %s actual=%.2f twin=%s%.2f [%.2f, %.2f] theil_sen=%s%.2f [%.2f, %.2f] %s",
                  static_cast<unsigned long long>(obs.index), prognosis::to_string(kAll[l]), actual,
                  twin[i].known ? "" : "unknown ", twin[i].hours, twin[i].low, twin[i].high, ts[i].known ? "" : "unknown ",
                  ts[i].hours, ts[i].low, ts[i].high, twin[i].why.c_str());
    trace.emplace_back(line);
  }
}

std::string score_table(const std::string& title, const MethodScores& twin, const MethodScores& baseline) {
  std::string out = title + "\n";
  char buf[300];
  std::snprintf(buf, sizeof buf, "| %-11s | %-10s | %9s | %6s | %15s | %13s | %14s | %7s | %13s | %14s |\n", "level", "method",
                "decisions", "known", "coverage(known)", "coverage(all)", "median|err| h", "reached", "truth earlier",
                "median width h");
  out += buf;
  out += "|-------------|------------|-----------|--------|-----------------|---------------|----------------|---------|---------------|----------------|\n";
  for (int l = 0; l < kLevels; ++l) {
    for (int m = 0; m < 2; ++m) {
      const LevelScore& s = (m == 0 ? twin : baseline).level[static_cast<std::size_t>(l)];
      const double d = static_cast<double>(s.decisions);
      std::snprintf(buf, sizeof buf, "| %-11s | %-10s | %9llu | %5.1f%% | %14.1f%% | %12.1f%% | %14.2f | %7llu | %12.1f%% | %14.2f |\n",
                    prognosis::to_string(kAll[l]), m == 0 ? "twin" : "theil-sen",
                    static_cast<unsigned long long>(s.decisions), s.decisions ? 100.0 * s.known / d : 0.0,
                    s.known ? 100.0 * s.covered / static_cast<double>(s.known) : 0.0, s.decisions ? 100.0 * s.covered / d : 0.0,
                    median_of(s.abs_errors), static_cast<unsigned long long>(s.reached_early),
                    s.known ? 100.0 * static_cast<double>(s.truth_earlier) / static_cast<double>(s.known) : 0.0,
                    median_of(s.widths));
      out += buf;
    }
  }
  return out;
}

PrognosisScorer score_simulated_run(const SimRun& run, const prognosis::PrognosisParams& params) {
  auto engine = std::make_unique<alarms::AlarmEngine>("sim", std::vector<std::string>{"wearing", "healthy"},
                                                      std::vector<std::string>{}, alarms::AlarmParams{});
  PrognosisScorer s(std::move(engine), params, 0,
                    {run.crossing_ns(2.0), run.crossing_ns(4.0), run.crossing_ns(params.end_of_life_ratio)});
  for (std::size_t i = 0; i < run.time_ns.size(); ++i) {
    alarms::Observation obs;
    obs.index = i;
    obs.time_ns = run.time_ns[i];
    obs.discontinuity = run.discontinuity[i];
    obs.features = run.features.row(static_cast<Eigen::Index>(i)).transpose();
    s.observe(obs);
  }
  return s;
}

}  // namespace causal::prognosis_eval
