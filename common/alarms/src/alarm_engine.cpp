#include "causal/alarms/alarm_engine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "engine_internal.hpp"

namespace causal::alarms {

using detail::kNaN;

namespace {

bool size_ok(const Eigen::VectorXd& v, Eigen::Index n) { return v.size() == 0 || v.size() == n; }

void finalize_signal(detail::SignalMonitor& s, const AlarmParams& p, double clip, double cap) {
  s.stats = robust_stats(s.baseline);
  // Guaranteed-performance margins for an estimated baseline (AlarmParams::baseline_confidence):
  // asymptotic Gaussian sd of MAD / MAD = 1.166 / sqrt(n), sd of the median = 1.2533 sigma / sqrt(n).
  const double q = normal_upper_quantile(1.0 - p.baseline_confidence);
  const double n = std::max<double>(1.0, static_cast<double>(s.stats.count));
  s.scale_inflation = 1.0 + q * 1.166 / std::sqrt(n);
  s.location_margin = q * 1.2533 / std::sqrt(n);
  const double needed = p.min_baseline_coverage * static_cast<double>(p.baseline_observations);
  s.monitored = s.stats.valid && static_cast<double>(s.stats.count) >= needed;
  s.cusum = ClippedCusum(p.cusum_k, clip, cap);
  s.level = WindowMean(p.level_window);
  s.reference_location = s.stats.location;
  s.anchor_location = s.stats.location;
  s.baseline.clear();
  s.baseline.shrink_to_fit();
}

}  // namespace

AlarmEngine::AlarmEngine(std::string asset_group, std::vector<std::string> channel_names,
                         std::vector<std::string> factor_names, AlarmParams params)
    : impl_(std::make_unique<Impl>()) {
  if (channel_names.empty()) throw std::invalid_argument("AlarmEngine: channel_names must not be empty");
  params.validate();
  Impl& m = *impl_;
  m.group = std::move(asset_group);
  m.names = std::move(channel_names);
  m.factor_names = std::move(factor_names);
  m.p = params;
  m.h = params.cusum_threshold();
  m.nis_thr = params.nis_threshold();
  const int g = m.channels();
  m.ch.resize(static_cast<std::size_t>(g));
  for (auto& c : m.ch) {
    for (int k = 0; k < detail::kKindCount; ++k) {
      const int raise = k == detail::kFactor                              ? params.factor_persistence
                        : k == detail::kInnovation || k == detail::kNis ? params.innovation_persistence
                                                                        : params.raise_persistence;
      c.slots[static_cast<std::size_t>(k)].latch = PersistenceLatch(raise, params.clear_persistence);
    }
    c.nis = WindowMean(params.nis_window);
  }
  m.fac.resize(m.factor_names.size());
  for (std::size_t i = 0; i < m.factor_names.size(); ++i) {
    m.fac[i].ref = parse_factor_name(m.factor_names[i], g);
    if (m.fac[i].ref.valid()) m.ch[static_cast<std::size_t>(m.fac[i].ref.outcome)].factors.push_back(static_cast<int>(i));
  }
  m.episode.reset(g);
}

AlarmEngine::~AlarmEngine() = default;
AlarmEngine::AlarmEngine(AlarmEngine&&) noexcept = default;
AlarmEngine& AlarmEngine::operator=(AlarmEngine&&) noexcept = default;

namespace {

using Impl = AlarmEngine::Impl;

// A latch transition, escalation or re-evaluated root cause of one (channel, kind), turned into an event once
// every detector of the observation has been read (simultaneous onsets see each other).
struct Pending {
  int c, kind;
  AlarmState state;
  std::string note;  // prefix of the reason (a re-evaluated root cause)
};

// The observation's per-channel values as the detectors see them: the (log) condition feature, and the
// innovation signal (log mean NIS when the observation summarises many samples, else e / sqrt(S)); NaN where
// there is none, and a non-finite or non-positive value is counted as rejected.
void transform_inputs(Impl& m, const Observation& obs, std::vector<double>& feat, std::vector<double>& innov) {
  const int g = m.channels();
  const auto G = static_cast<Eigen::Index>(g);
  for (int c = 0; c < g; ++c) {
    auto& cs = m.ch[static_cast<std::size_t>(c)];
    if (obs.features.size() == G) {
      const double v = obs.features(c);
      if (std::isfinite(v) && (!m.p.feature_log_transform || v > 0.0))
        feat[static_cast<std::size_t>(c)] = m.p.feature_log_transform ? std::log(v) : v;
      else
        ++cs.rejected;
    }
    if (obs.mean_nis.size() == G && std::isfinite(obs.mean_nis(c))) {
      if (obs.mean_nis(c) > 0.0) {
        innov[static_cast<std::size_t>(c)] = std::log(obs.mean_nis(c));
        if (!m.ready) ++cs.baseline_from_nis;
      } else {
        ++cs.rejected;
      }
    } else if (obs.innovations.size() == G) {
      const double e = obs.innovations(c), s = obs.innovation_variances(c);
      if (std::isfinite(e) && std::isfinite(s) && s > 0.0) {
        innov[static_cast<std::size_t>(c)] = e / std::sqrt(s);
        if (!m.ready) ++cs.baseline_from_filter;
      } else if (!std::isnan(e)) {
        ++cs.rejected;  // NaN innovation = "none this time" (e.g. filter warm-up), not an error
      }
    }
  }
}

// Baseline collection; at its last observation the statistics, margins and the usual interval are fixed.
void collect_baseline(Impl& m, const Observation& obs, const std::vector<double>& feat,
                      const std::vector<double>& innov, bool last) {
  for (int c = 0; c < m.channels(); ++c) {
    auto& cs = m.ch[static_cast<std::size_t>(c)];
    cs.feature.baseline.push_back(feat[static_cast<std::size_t>(c)]);
    cs.innovation.baseline.push_back(innov[static_cast<std::size_t>(c)]);
  }
  for (Eigen::Index i = 0; i < obs.factors.size(); ++i) m.fac[static_cast<std::size_t>(i)].baseline.push_back(obs.factors(i));
  m.baseline_times.push_back(obs.time_ns);
  if (!last) return;
  const double cap = m.p.cusum_cap_factor * m.h;
  for (auto& cs : m.ch) {
    // The healthy range (warm-up and baseline): a level inside it is no degradation (AlarmParams::advisory_ratio).
    const double top = detail::healthy_range_top(cs.feature.warmup, cs.feature.baseline, m.p.level_window);
    cs.feature.warmup.clear();
    cs.feature.warmup.shrink_to_fit();
    finalize_signal(cs.feature, m.p, m.p.clip_sigma, cap);
    if (m.p.feature_log_transform) cs.feature.healthy_top = top - cs.feature.stats.location;
    cs.feature.range_left = std::max(0, m.p.healthy_range_observations - m.p.warmup_observations - m.p.baseline_observations);
    finalize_signal(cs.innovation, m.p, m.p.clip_sigma, cap);
  }
  for (auto& f : m.fac) {
    f.stats = robust_stats(f.baseline);
    f.monitored = f.stats.valid &&
                  static_cast<double>(f.stats.count) >= m.p.min_baseline_coverage * m.p.baseline_observations;
    f.baseline.clear();
    f.baseline.shrink_to_fit();
  }
  // The usual interval: median of the positive steps between baseline observations (0 = unknown,
  // e.g. no time stamps: then only flagged discontinuities count).
  std::vector<double> dt;
  for (std::size_t i = 1; i < m.baseline_times.size(); ++i)
    if (m.baseline_times[i] > m.baseline_times[i - 1])
      dt.push_back(static_cast<double>(m.baseline_times[i] - m.baseline_times[i - 1]));
  m.median_interval_ns = dt.empty() ? 0.0 : median(dt);
  m.baseline_times.clear();
  m.baseline_times.shrink_to_fit();
  m.ready = true;
}

// The operating-state gate (AlarmParams::stopped_ratio): true when every monitored channel's level fell below
// stopped_ratio x its baseline (the machine is not running: nothing is judged).
bool machine_stopped(const Impl& m, const Observation& obs, const std::vector<double>& feat) {
  if (!m.p.feature_log_transform || !(m.p.stopped_ratio > 0.0) || obs.features.size() != static_cast<Eigen::Index>(m.channels()))
    return false;
  const double drop = std::log(m.p.stopped_ratio);
  int checked = 0, below = 0;
  for (int c = 0; c < m.channels(); ++c) {
    const auto& f = m.ch[static_cast<std::size_t>(c)].feature;
    if (!f.monitored || !std::isfinite(feat[static_cast<std::size_t>(c)])) continue;
    ++checked;
    below += feat[static_cast<std::size_t>(c)] - f.stats.location < drop ? 1 : 0;
  }
  return checked > 0 && below == checked;
}

// Every factor's z against its baseline (the baseline spread and the current estimation uncertainty add in
// quadrature: a factor counts as moved only when it left both its usual range and its own error bar).
void update_factors(Impl& m, const Observation& obs) {
  const auto F = static_cast<Eigen::Index>(m.fac.size());
  const double factor_inflation =
      1.0 + normal_upper_quantile(1.0 - m.p.baseline_confidence) * 1.166 /
                std::sqrt(std::max(1.0, static_cast<double>(m.p.baseline_observations)));
  for (std::size_t i = 0; i < m.fac.size(); ++i) {
    auto& f = m.fac[i];
    f.last_value = obs.factors.size() == F ? obs.factors(static_cast<Eigen::Index>(i)) : kNaN;
    f.last_std = obs.factor_std.size() == F ? obs.factor_std(static_cast<Eigen::Index>(i)) : 0.0;
    if (!std::isfinite(f.last_std) || f.last_std < 0.0) f.last_std = 0.0;
    const double scale = f.stats.scale * factor_inflation;
    f.last_z = f.monitored && std::isfinite(f.last_value)
                   ? (f.last_value - f.stats.location) / std::sqrt(scale * scale + f.last_std * f.last_std)
                   : kNaN;
  }
}

// Channel c's signals: feature and innovation CUSUMs, the own-change evidence of an excursion, the NIS
// window and the largest factor z of the factors into c.
void update_channel(Impl& m, int c, const Observation& obs, double feat, double innov) {
  auto& cs = m.ch[static_cast<std::size_t>(c)];
  detail::update_signal(cs.feature, feat, m.p, obs, !cs.any_active());
  detail::update_signal(cs.innovation, innov, m.p, obs, false);
  if (!cs.feature.cusum.in_excursion() || cs.feature.cusum.onset_index() == obs.index) {
    cs.own_sum = 0.0;  // no excursion, or one that starts now: restart the evidence
    cs.own_count = 0;
  }
  detail::update_step_run(cs, m.p);
  if (cs.feature.cusum.in_excursion() && std::isfinite(cs.innovation.last_z)) {
    cs.own_sum += std::max(-m.p.clip_sigma, std::min(m.p.clip_sigma, cs.innovation.last_z));
    ++cs.own_count;
  }
  if (std::isfinite(cs.innovation.last_z)) {
    const double z = std::min(m.p.nis_two_sided ? std::abs(cs.innovation.nis_z) : std::max(0.0, cs.innovation.nis_z),
                              m.p.clip_sigma);
    cs.nis.push(z * z);
  }
  cs.factor_stat = kNaN;
  cs.factor_argmax = -1;
  for (int i : cs.factors) {
    const double z = m.fac[static_cast<std::size_t>(i)].last_z;
    if (std::isfinite(z) && (!std::isfinite(cs.factor_stat) || std::abs(z) > cs.factor_stat)) {
      cs.factor_stat = std::abs(z);
      cs.factor_argmax = i;
    }
  }
}

// Phase 1, the detector table: every kind of every channel read, its latch updated; raises, clears and
// escalations collected. Evidence AND size: below the size floor (AlarmParams::advisory_ratio) nothing is raised.
std::vector<Pending> read_detectors(Impl& m, const Observation& obs) {
  std::vector<Pending> pending;
  for (int c = 0; c < m.channels(); ++c) {
    auto& cs = m.ch[static_cast<std::size_t>(c)];
    const bool sized = detail::size_matters(m, c);
    for (int k = 0; k < detail::kKindCount; ++k) {
      auto& slot = cs.slots[static_cast<std::size_t>(k)];
      const detail::DetectorReading r = detail::detector_table()[static_cast<std::size_t>(k)].read(m, c, obs);
      if (!r.enabled) continue;
      slot.score = r.statistic;
      slot.threshold = r.threshold;
      const auto t = slot.latch.update(r.statistic, sized ? r.threshold : std::numeric_limits<double>::infinity(), m.p.clear_fraction * r.threshold);
      if (t == PersistenceLatch::Transition::Raise) {
        m.begin_alarm(c, k, obs);
        pending.push_back({c, k, AlarmState::Raised, {}});
      } else if (t == PersistenceLatch::Transition::Clear) {
        pending.push_back({c, k, AlarmState::Cleared, {}});
      } else if (slot.latch.active() && m.escalate(c, k)) {
        pending.push_back({c, k, AlarmState::Escalated, {}});
      }
    }
  }
  return pending;
}

// The root cause of every active alarm re-evaluated on the evidence accumulated so far; a changed verdict
// prefixes the alarm's event of this observation, or becomes an escalation event of its own.
void reevaluate_roots(Impl& m, const std::vector<double>& evidence, std::vector<Pending>& pending) {
  for (int c = 0; c < m.channels(); ++c) {
    auto& cs = m.ch[static_cast<std::size_t>(c)];
    for (int k = 0; k < detail::kKindCount; ++k) {
      auto& slot = cs.slots[static_cast<std::size_t>(k)];
      if (!slot.latch.active() || slot.root < 0) continue;  // new alarms get their root in phase 2
      const bool has_event = std::any_of(pending.begin(), pending.end(), [&](const Pending& pe) { return pe.c == c && pe.kind == k; });
      std::string why = m.reevaluate_root(c, slot, evidence);
      if (why.empty()) continue;
      auto it = std::find_if(pending.begin(), pending.end(), [&](const Pending& pe) { return pe.c == c && pe.kind == k; });
      if (has_event && it != pending.end())
        it->note = why + " ";
      else
        pending.push_back({c, k, AlarmState::Escalated, why + " "});
    }
  }
}

// Phase 2: the events, with root cause, its confidence and the explanation.
void make_events(Impl& m, const Observation& obs, const std::vector<double>& evidence,
                 const std::vector<Pending>& pending, std::vector<AlarmEvent>& events) {
  events.reserve(pending.size());
  for (const auto& pe : pending) {
    auto& slot = m.ch[static_cast<std::size_t>(pe.c)].slots[static_cast<std::size_t>(pe.kind)];
    if (pe.state == AlarmState::Raised) slot.root = m.root_cause(pe.c, slot.onset_index);
    slot.root_confidence = m.attribution_confidence(slot.root, evidence);
    AlarmEvent e = m.make_event(pe.c, pe.kind, pe.state, obs);
    e.reason = pe.note + e.reason;
    slot.last_event = e;
    events.push_back(std::move(e));
  }
}

// The warm-up's log features: part of the channel's healthy range (SignalMonitor::healthy_top), not of its
// baseline (the filter's transient concerns the innovations, not the levels).
void collect_warmup(Impl& m, const Observation& obs) {
  if (!m.p.feature_log_transform || obs.features.size() != static_cast<Eigen::Index>(m.channels())) return;
  for (int c = 0; c < m.channels(); ++c) {
    const double v = obs.features(c);
    m.ch[static_cast<std::size_t>(c)].feature.warmup.push_back(std::isfinite(v) && v > 0.0 ? std::log(v) : kNaN);
  }
}

// While the group is held for a confirmation window (a gap or a step), a channel with an open alarm keeps its
// baseline and its level is still judged: a failure that goes on rising across a short recording gap
// escalates at once (its detectors' latches stay held; only the level event and the severity move).
void escalate_during_confirmation(Impl& m, const Observation& obs, const std::vector<double>& feat,
                                  std::vector<AlarmEvent>& events) {
  std::vector<Pending> pending;
  for (int c = 0; c < m.channels(); ++c) {
    auto& cs = m.ch[static_cast<std::size_t>(c)];
    if (!cs.any_active() || !std::isfinite(feat[static_cast<std::size_t>(c)])) continue;
    detail::update_signal(cs.feature, feat[static_cast<std::size_t>(c)], m.p, obs, false);
    detail::update_level_event(m, c);
    for (int k = 0; k < detail::kKindCount; ++k)
      if (cs.slots[static_cast<std::size_t>(k)].latch.active() && m.escalate(c, k)) pending.push_back({c, k, AlarmState::Escalated, {}});
  }
  if (!pending.empty()) make_events(m, obs, m.departed_evidence(), pending, events);
}

}  // namespace

std::vector<AlarmEvent> AlarmEngine::observe(const Observation& obs) {
  Impl& m = *impl_;
  const int g = m.channels();
  const auto G = static_cast<Eigen::Index>(g);
  const auto F = static_cast<Eigen::Index>(m.fac.size());
  const bool sizes = size_ok(obs.features, G) && size_ok(obs.innovations, G) &&
                     obs.innovation_variances.size() == obs.innovations.size() && size_ok(obs.mean_nis, G) &&
                     size_ok(obs.factors, F) && (obs.factor_std.size() == 0 || obs.factor_std.size() == obs.factors.size());
  if (!sizes) {
    ++m.rejected;
    return {};
  }
  const std::uint64_t n = m.seen++;
  const auto warm = static_cast<std::uint64_t>(m.p.warmup_observations);
  const auto base_end = warm + static_cast<std::uint64_t>(m.p.baseline_observations);
  // Input lost before the engine (skipped indices of a consecutive source): reported, and no gap.
  std::vector<AlarmEvent> events;
  const detail::LostRange lost = m.continuity.step(obs.index, obs.time_ns);
  if (lost.count > 0) m.report_lost(lost, obs, events);
  // Time awareness: judged against the previous observation's time, whatever happens to this one.
  const bool discontinuity = m.ready && m.is_discontinuity(obs, lost.count);
  const double gap_s = m.has_last_time ? static_cast<double>(obs.time_ns - m.last_time_ns) * 1e-9 : 0.0;
  m.has_last_time = true;
  m.last_time_ns = obs.time_ns;
  if (n < warm) {
    collect_warmup(m, obs);
    return events;
  }

  std::vector<double> feat(static_cast<std::size_t>(g), kNaN), innov(static_cast<std::size_t>(g), kNaN);
  transform_inputs(m, obs, feat, innov);
  if (!m.ready) {
    collect_baseline(m, obs, feat, innov, n + 1 == base_end);
    return events;
  }
  if (machine_stopped(m, obs, feat)) {
    ++m.not_running;
    m.stopped = true;
    return events;
  }
  // Running again after a stop: the machine restarted, levels may differ (a discontinuity, as a gap).
  const bool restarted = m.stopped;
  m.stopped = false;

  // Gaps: hold the detectors and re-baseline after the confirmation window.
  if (discontinuity || restarted) {
    ++m.discontinuities;
    m.start_confirmation(obs, true, -1, (obs.discontinuity && lost.count == 0) || !discontinuity ? 0.0 : gap_s);
    m.confirm.restart = restarted && !discontinuity;
  }
  if (m.confirm.active) {
    escalate_during_confirmation(m, obs, feat, events);
    m.confirm_step(obs, feat, innov, events);
    return events;
  }

  update_factors(m, obs);
  for (int c = 0; c < g; ++c) {
    update_channel(m, c, obs, feat[static_cast<std::size_t>(c)], innov[static_cast<std::size_t>(c)]);
    detail::update_level_event(m, c);
  }

  // Abrupt steps: confirm before alarming (AlarmParams::operating_step_ratio).
  if (const int step = m.abrupt_step(); step >= 0) {
    m.start_confirmation(obs, false, step, 0.0);
    m.confirm_step(obs, feat, innov, events);
    return events;
  }

  std::vector<Pending> pending = read_detectors(m, obs);
  const std::vector<double> evidence = m.departed_evidence();
  reevaluate_roots(m, evidence, pending);
  make_events(m, obs, evidence, pending, events);

  bool any_active = false;
  for (const auto& cs : m.ch) any_active = any_active || cs.any_active();
  if (!any_active) m.episode.reset(g);
  return events;
}

void AlarmEngine::Impl::begin_alarm(int c, int k, const Observation& obs) {
  auto& slot = ch[static_cast<std::size_t>(c)].slots[static_cast<std::size_t>(k)];
  ++slot.counter;
  slot.id = alarm_id(c, detail::kind_name(k), slot.counter);
  slot.raised_time_ns = obs.time_ns;
  detail::detector_table()[static_cast<std::size_t>(k)].onset(*this, c, obs, slot.onset_index, slot.onset_time_ns);
  slot.warning_run = slot.critical_run = 0;
  slot.severity = Severity::Advisory;
  escalate(c, k);  // counts this observation's level (persistence 1 escalates at once, as before)
  slot.root = -1;
  slot.challenger = -1;
  slot.challenger_run = 0;
}

AlarmEvent AlarmEngine::Impl::make_event(int c, int k, AlarmState state, const Observation& obs) {
  auto& slot = ch[static_cast<std::size_t>(c)].slots[static_cast<std::size_t>(k)];
  AlarmEvent e;
  e.alarm_id = slot.id;
  e.channel = c;
  e.severity = slot.severity;
  e.state = state;
  e.kind = detail::kind_name(k);
  e.category = detail::detector_table()[static_cast<std::size_t>(k)].category;
  e.raised_time_ns = slot.raised_time_ns;
  e.cleared_time_ns = state == AlarmState::Cleared ? obs.time_ns : 0;
  e.index = obs.index;
  e.onset_index = slot.onset_index;
  e.onset_time_ns = slot.onset_time_ns;
  e.root_cause_channel = slot.root;
  e.root_cause_confidence = slot.root_confidence;
  for (int i : explain_factors(c, e.root_cause_channel)) {
    const auto& f = fac[static_cast<std::size_t>(i)];
    e.factor_names.push_back(factor_names[static_cast<std::size_t>(i)]);
    e.factor_baseline.push_back(f.stats.location);
    e.factor_now.push_back(f.last_value);
  }
  e.score = slot.score;
  e.threshold = slot.threshold;
  e.reason = reason(c, k, state, e.root_cause_channel, obs);
  return e;
}

bool AlarmEngine::baseline_ready() const { return impl_->ready; }
int AlarmEngine::channel_count() const { return impl_->channels(); }
const std::string& AlarmEngine::asset_group() const { return impl_->group; }
void AlarmEngine::set_id_scope(std::string scope) { impl_->id_scope = std::move(scope); }
const std::vector<std::string>& AlarmEngine::channel_names() const { return impl_->names; }
const std::vector<std::string>& AlarmEngine::factor_names() const { return impl_->factor_names; }
const AlarmParams& AlarmEngine::params() const { return impl_->p; }
double AlarmEngine::cusum_threshold() const { return impl_->h; }
double AlarmEngine::nis_threshold() const { return impl_->nis_thr; }
std::uint64_t AlarmEngine::observations_seen() const { return impl_->seen; }
std::uint64_t AlarmEngine::rejected_observations() const { return impl_->rejected; }
std::uint64_t AlarmEngine::not_running_observations() const { return impl_->not_running; }
std::uint64_t AlarmEngine::discontinuities() const { return impl_->discontinuities; }
std::uint64_t AlarmEngine::operating_changes() const { return impl_->operating_changes; }
std::uint64_t AlarmEngine::lost_observations() const { return impl_->continuity.lost; }
std::uint64_t AlarmEngine::input_losses() const { return impl_->continuity.losses; }

ChannelDiagnostics AlarmEngine::channel_diagnostics(int channel) const {
  const Impl& m = *impl_;
  if (channel < 0 || channel >= m.channels()) throw std::invalid_argument("channel_diagnostics: channel out of range");
  const auto& cs = m.ch[static_cast<std::size_t>(channel)];
  auto sig = [](const detail::SignalMonitor& s) {
    SignalDiagnostics d;
    d.monitored = s.monitored;
    d.baseline_location = s.stats.location;
    d.baseline_scale = s.stats.scale;
    d.baseline_lag1_autocorr = s.stats.lag1_autocorr;
    d.last_z = s.last_z;
    d.cusum = s.cusum.value();
    return d;
  };
  ChannelDiagnostics d;
  d.feature = sig(cs.feature);
  d.innovation = sig(cs.innovation);
  d.nis_window_mean = cs.nis.mean();
  d.factor_max_abs_z = cs.factor_stat;
  for (int i : cs.factors) d.monitored_factors += m.fac[static_cast<std::size_t>(i)].monitored ? 1 : 0;
  d.rejected_values = cs.rejected;
  bool active = false;
  std::uint64_t since = ~std::uint64_t{0};
  for (const auto& s : cs.slots)
    if (s.latch.active()) {
      active = true;
      since = std::min(since, s.onset_index);
    }
  d.root_cause = active ? m.root_cause(channel, since) : -1;
  return d;
}

std::vector<AlarmEvent> AlarmEngine::active_alarms() const {
  std::vector<AlarmEvent> out;
  for (const auto& cs : impl_->ch)
    for (const auto& s : cs.slots)
      if (s.latch.active()) out.push_back(s.last_event);
  return out;
}

}  // namespace causal::alarms
