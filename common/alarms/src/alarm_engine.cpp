#include "causal/alarms/alarm_engine.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "engine_internal.hpp"

namespace causal::alarms {

using detail::kNaN;

namespace detail {
const char* kind_name(int kind_index) {
  switch (kind_index) {
    case kFeature: return kind::kFeatureDrift;
    case kInnovation: return kind::kInnovationRise;
    case kNis: return kind::kInnovationNis;
    case kFactor: return kind::kFactorShift;
    default: return "?";
  }
}
}  // namespace detail

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
      const int raise = k == detail::kFactor ? params.factor_persistence : params.raise_persistence;
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
  if (n < warm) return {};

  // ---- transformed per-channel values ------------------------------------------------------------
  std::vector<double> feat(static_cast<std::size_t>(g), kNaN), innov(static_cast<std::size_t>(g), kNaN);
  for (int c = 0; c < g; ++c) {
    auto& cs = m.ch[static_cast<std::size_t>(c)];
    if (obs.features.size() == G) {
      const double v = obs.features(c);
      if (std::isfinite(v) && (!m.p.feature_log_transform || v > 0.0))
        feat[static_cast<std::size_t>(c)] = m.p.feature_log_transform ? std::log(v) : v;
      else
        ++cs.rejected;
    }
    // Innovation signal: log mean NIS when the observation summarises many samples, else e / sqrt(S).
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

  if (!m.ready) {  // ---- baseline collection --------------------------------------------------------
    for (int c = 0; c < g; ++c) {
      auto& cs = m.ch[static_cast<std::size_t>(c)];
      cs.feature.baseline.push_back(feat[static_cast<std::size_t>(c)]);
      cs.innovation.baseline.push_back(innov[static_cast<std::size_t>(c)]);
    }
    for (Eigen::Index i = 0; i < obs.factors.size(); ++i) m.fac[static_cast<std::size_t>(i)].baseline.push_back(obs.factors(i));
    if (n + 1 == base_end) {
      const double cap = m.p.cusum_cap_factor * m.h;
      for (auto& cs : m.ch) {
        finalize_signal(cs.feature, m.p, m.p.clip_sigma, cap);
        finalize_signal(cs.innovation, m.p, m.p.clip_sigma, cap);
      }
      for (auto& f : m.fac) {
        f.stats = robust_stats(f.baseline);
        f.monitored = f.stats.valid &&
                      static_cast<double>(f.stats.count) >= m.p.min_baseline_coverage * m.p.baseline_observations;
        f.baseline.clear();
        f.baseline.shrink_to_fit();
      }
      m.ready = true;
    }
    return {};
  }

  // ---- operating-state gate (AlarmParams::stopped_ratio) -------------------------------------------
  if (m.p.feature_log_transform && m.p.stopped_ratio > 0.0 && obs.features.size() == G) {
    const double drop = std::log(m.p.stopped_ratio);
    int checked = 0, below = 0;
    for (int c = 0; c < g; ++c) {
      const auto& f = m.ch[static_cast<std::size_t>(c)].feature;
      if (!f.monitored || !std::isfinite(feat[static_cast<std::size_t>(c)])) continue;
      ++checked;
      below += feat[static_cast<std::size_t>(c)] - f.stats.location < drop ? 1 : 0;
    }
    if (checked > 0 && below == checked) {
      ++m.not_running;
      return {};
    }
  }

  // ---- update the detectors -----------------------------------------------------------------------
  const double factor_inflation =
      1.0 + normal_upper_quantile(1.0 - m.p.baseline_confidence) * 1.166 /
                std::sqrt(std::max(1.0, static_cast<double>(m.p.baseline_observations)));
  for (std::size_t i = 0; i < m.fac.size(); ++i) {
    auto& f = m.fac[i];
    f.last_value = obs.factors.size() == F ? obs.factors(static_cast<Eigen::Index>(i)) : kNaN;
    f.last_std = obs.factor_std.size() == F ? obs.factor_std(static_cast<Eigen::Index>(i)) : 0.0;
    if (!std::isfinite(f.last_std) || f.last_std < 0.0) f.last_std = 0.0;
    // The baseline spread (MAD) and the current estimation uncertainty (std) add in quadrature: a factor
    // counts as moved only when it left both its usual range and its own error bar.
    const double scale = f.stats.scale * factor_inflation;
    f.last_z = f.monitored && std::isfinite(f.last_value)
                   ? (f.last_value - f.stats.location) / std::sqrt(scale * scale + f.last_std * f.last_std)
                   : kNaN;
  }
  for (int c = 0; c < g; ++c) {
    auto& cs = m.ch[static_cast<std::size_t>(c)];
    auto update_signal = [&](detail::SignalMonitor& s, double v) {
      s.last_value = v;
      s.last_z = s.monitored && std::isfinite(v) ? s.standardize(v) : kNaN;
      s.nis_z = s.last_z / s.scale_inflation;
      s.detect_z = s.nis_z - s.location_margin;
      if (std::isfinite(s.last_z)) {
        s.cusum.update(s.detect_z, obs.index, obs.time_ns);
        s.level.push(s.last_z);
      }
    };
    update_signal(cs.feature, feat[static_cast<std::size_t>(c)]);
    update_signal(cs.innovation, innov[static_cast<std::size_t>(c)]);
    if (!cs.feature.cusum.in_excursion() || cs.feature.cusum.onset_index() == obs.index) {
      cs.own_sum = 0.0;  // no excursion, or one that starts now: restart the evidence
      cs.own_count = 0;
    }
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

  // ---- phase 1: latch transitions and episode onsets ---------------------------------------------
  struct Pending {
    int c, kind;
    AlarmState state;
  };
  std::vector<Pending> pending;
  for (int c = 0; c < g; ++c) {
    auto& cs = m.ch[static_cast<std::size_t>(c)];
    for (int k = 0; k < detail::kKindCount; ++k) {
      auto& slot = cs.slots[static_cast<std::size_t>(k)];
      double stat = kNaN, thr = 0.0;
      bool enabled = true;
      switch (k) {
        case detail::kFeature:
          enabled = m.p.feature_enabled && cs.feature.monitored;
          stat = std::isfinite(cs.feature.last_z) ? cs.feature.cusum.value() : kNaN;
          thr = m.h;
          break;
        case detail::kInnovation:
          enabled = m.p.innovation_enabled && cs.innovation.monitored;
          stat = std::isfinite(cs.innovation.last_z) ? cs.innovation.cusum.value() : kNaN;
          thr = m.h;
          break;
        case detail::kNis:
          enabled = m.p.nis_enabled && cs.innovation.monitored;
          stat = std::isfinite(cs.innovation.last_z) && cs.nis.full() ? cs.nis.mean() : kNaN;
          thr = m.nis_thr;
          break;
        default: {
          int monitored = 0;
          for (int i : cs.factors) monitored += m.fac[static_cast<std::size_t>(i)].monitored ? 1 : 0;
          enabled = m.p.factor_enabled && monitored > 0;
          stat = cs.factor_stat;
          thr = m.p.factor_threshold(monitored);
          if (std::isfinite(stat) && stat >= thr && !cs.factor_in_run) {
            cs.factor_in_run = true;
            cs.factor_run_start_index = obs.index;
            cs.factor_run_start_time_ns = obs.time_ns;
          } else if (std::isfinite(stat) && stat < thr) {
            cs.factor_in_run = false;
          }
          break;
        }
      }
      if (!enabled) continue;
      slot.score = stat;
      slot.threshold = thr;
      const auto t = slot.latch.update(stat, thr, m.p.clear_fraction * thr);
      if (t == PersistenceLatch::Transition::Raise) {
        ++slot.counter;
        slot.id = m.group + "/" + std::to_string(c + 1) + "/" + detail::kind_name(k) + "/" + std::to_string(slot.counter);
        slot.raised_time_ns = obs.time_ns;
        switch (k) {
          case detail::kFeature:
            slot.onset_index = cs.feature.cusum.onset_index();
            slot.onset_time_ns = cs.feature.cusum.onset_time_ns();
            m.episode.departure[static_cast<std::size_t>(c)].take_earlier(slot.onset_index, slot.onset_time_ns,
                                                                          cs.feature.level.median(), cs.own_evidence());
            break;
          case detail::kInnovation:
            slot.onset_index = cs.innovation.cusum.onset_index();
            slot.onset_time_ns = cs.innovation.cusum.onset_time_ns();
            m.episode.own[static_cast<std::size_t>(c)].take_earlier(slot.onset_index, slot.onset_time_ns,
                                                                    cs.innovation.level.median());
            break;
          case detail::kFactor:
            slot.onset_index = cs.factor_run_start_index;
            slot.onset_time_ns = cs.factor_run_start_time_ns;
            break;
          default:  // NIS: the window has no sharp change point; use the raise itself
            slot.onset_index = obs.index;
            slot.onset_time_ns = obs.time_ns;
            break;
        }
        slot.severity = m.severity_for(c, k);
        pending.push_back({c, k, AlarmState::Raised});
      } else if (t == PersistenceLatch::Transition::Clear) {
        pending.push_back({c, k, AlarmState::Cleared});
      } else if (slot.latch.active()) {
        const Severity s = m.severity_for(c, k);
        if (static_cast<int>(s) > static_cast<int>(slot.severity)) {  // severities only escalate
          slot.severity = s;
          pending.push_back({c, k, AlarmState::Escalated});
        }
      }
    }
  }

  // ---- phase 2: events with root cause and explanation ---------------------------------------------
  std::vector<AlarmEvent> events;
  events.reserve(pending.size());
  for (const auto& pe : pending) {
    auto& slot = m.ch[static_cast<std::size_t>(pe.c)].slots[static_cast<std::size_t>(pe.kind)];
    AlarmEvent e;
    e.alarm_id = slot.id;
    e.channel = pe.c;
    e.severity = slot.severity;
    e.state = pe.state;
    e.kind = detail::kind_name(pe.kind);
    e.raised_time_ns = slot.raised_time_ns;
    e.cleared_time_ns = pe.state == AlarmState::Cleared ? obs.time_ns : 0;
    e.index = obs.index;
    e.onset_index = slot.onset_index;
    e.onset_time_ns = slot.onset_time_ns;
    e.root_cause_channel = m.root_cause(pe.c, slot.onset_index);
    for (int i : m.explain_factors(pe.c, e.root_cause_channel)) {
      const auto& f = m.fac[static_cast<std::size_t>(i)];
      e.factor_names.push_back(m.factor_names[static_cast<std::size_t>(i)]);
      e.factor_baseline.push_back(f.stats.location);
      e.factor_now.push_back(f.last_value);
    }
    e.score = slot.score;
    e.threshold = slot.threshold;
    e.reason = m.reason(pe.c, pe.kind, pe.state, e.root_cause_channel, obs);
    slot.last_event = e;
    events.push_back(std::move(e));
  }

  bool any_active = false;
  for (const auto& cs : m.ch)
    for (const auto& s : cs.slots) any_active = any_active || s.latch.active();
  if (!any_active) m.episode.reset(g);
  return events;
}

bool AlarmEngine::baseline_ready() const { return impl_->ready; }
int AlarmEngine::channel_count() const { return impl_->channels(); }
const std::string& AlarmEngine::asset_group() const { return impl_->group; }
const std::vector<std::string>& AlarmEngine::channel_names() const { return impl_->names; }
const std::vector<std::string>& AlarmEngine::factor_names() const { return impl_->factor_names; }
const AlarmParams& AlarmEngine::params() const { return impl_->p; }
double AlarmEngine::cusum_threshold() const { return impl_->h; }
double AlarmEngine::nis_threshold() const { return impl_->nis_thr; }
std::uint64_t AlarmEngine::observations_seen() const { return impl_->seen; }
std::uint64_t AlarmEngine::rejected_observations() const { return impl_->rejected; }
std::uint64_t AlarmEngine::not_running_observations() const { return impl_->not_running; }

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
