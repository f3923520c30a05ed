// Month-long simulated recordings: see ims_variants_month.hpp.
#include "ims_variants_month.hpp"
#include "variant_draws.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>

namespace causal::testing {
namespace {

constexpr std::int64_t kMinute = 60LL * 1000000000LL;
constexpr std::int64_t kHour = 60 * kMinute;
constexpr std::int64_t kT0 = 1076581959LL * 1000000000LL;  // 2004-02-12 10:32:39 UTC (IMS test 2's start)

// AR(1) with stationary standard deviation sd.
struct Ar1 {
  double phi, sd, x = 0.0;
  double next(Draws& d) {
    x = phi * x + sd * std::sqrt(1.0 - phi * phi) * d.normal();
    return x;
  }
};

double fault_log_rise(double tau, double t_x4) {
  if (tau < 0.0) return 0.0;
  return std::log(4.0) * (std::exp(4.0 * tau / t_x4) - 1.0) / (std::exp(4.0) - 1.0);
}

}  // namespace

double fault_rows_to_ratio(const MonthOptions& o, double ratio) {
  const double t = static_cast<double>(o.fault_rows_to_x4);
  return t / 4.0 * std::log(1.0 + std::log(ratio) / std::log(4.0) * (std::exp(4.0) - 1.0));
}

Variant make_month_variant(const MonthOptions& o, std::uint64_t seed) {
  if (o.bearings < 2 || o.sensors_per_bearing < 1) throw std::invalid_argument("month variant: need >= 2 bearings");
  const std::size_t rows = o.fault ? o.fault_start + o.fault_rows_to_x4 + 24 : o.rows;
  if (rows < 3000) throw std::invalid_argument("month variant: need at least 3000 rows");
  const int g = o.bearings * o.sensors_per_bearing;
  Draws d(seed * 0x9e3779b97f4a7c15ULL + static_cast<std::uint64_t>(g));
  Variant v;
  v.name = std::string(o.fault ? "month_fault_" : "month_healthy_") + (o.slow_wander > 0.0 ? "wander_" : "") +
           std::to_string(g) + "ch_s" + std::to_string(seed);
  for (int b = 0; b < o.bearings; ++b)
    for (int s = 0; s < o.sensors_per_bearing; ++s)
      v.channel_names.push_back("Bearing " + std::to_string(b + 1) +
                                (o.sensors_per_bearing > 1 ? " C" + std::to_string(s + 1) : std::string()));
  v.values.resize(static_cast<Eigen::Index>(rows), g);
  v.healthy_end = o.fault ? o.fault_start : rows;
  if (o.fault)
    for (int s = 0; s < o.sensors_per_bearing; ++s) v.failing_channels.push_back(s);

  std::vector<double> base(static_cast<std::size_t>(o.bearings)), drift(base.size()), amp(base.size());
  for (std::size_t b = 0; b < base.size(); ++b) {
    base[b] = std::log(d.uniform(0.045, 0.09));
    drift[b] = d.uniform(-0.06, 0.08);
    amp[b] = d.uniform(0.01, 0.02);
  }
  const double phase = d.uniform(0.0, 2.0 * M_PI);
  // Injections: per-channel cumulative log offsets from a row on.
  std::vector<double> offset(static_cast<std::size_t>(g), 0.0);
  std::vector<std::vector<std::pair<std::size_t, double>>> steps(static_cast<std::size_t>(g));
  const std::size_t gap_rows[3] = {d.index(400, 700), d.index(1400, 1700), d.index(2400, 2700)};
  const std::int64_t gap_ns[3] = {4 * kHour + static_cast<std::int64_t>(d.uniform() * 2.0 * kHour), 48 * kHour, 30 * kHour};
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < g; ++c) {
      const double f = d.uniform(1.15, 1.20);
      steps[static_cast<std::size_t>(c)].push_back({gap_rows[k], std::log(f)});
      v.injections.push_back({gap_rows[k], c, f, c == 0 ? gap_ns[k] : 0});
    }
  const std::size_t step_rows[2] = {d.index(900, 1200), d.index(2000, 2300)};
  for (std::size_t step_row : step_rows) {
    const int b = 1 + static_cast<int>(d.index(0, static_cast<std::size_t>(o.bearings - 1)));  // never bearing 0
    const double f = d.uniform(1.20, 1.40);
    for (int s = 0; s < o.sensors_per_bearing; ++s) {
      const int c = b * o.sensors_per_bearing + s;
      steps[static_cast<std::size_t>(c)].push_back({step_row, std::log(f)});
      v.injections.push_back({step_row, c, f, 0});
    }
  }
  std::vector<int> spike_channel(rows, -1);
  std::vector<double> spike_factor(rows, 1.0);
  const std::size_t spike_end = o.fault ? o.fault_start : rows;
  for (std::size_t day = 0; day * 144 + 144 <= spike_end; ++day) {
    const std::size_t r = d.index(std::max<std::size_t>(day * 144, 150), day * 144 + 144);
    if (r >= spike_end) continue;
    spike_channel[r] = static_cast<int>(d.index(0, static_cast<std::size_t>(g)));
    spike_factor[r] = d.uniform(1.5, 3.0);
  }

  // Slow wander and short excursions (MonthOptions): their own generator, so runs without them do not change.
  Draws extra(seed * 0xbf58476d1ce4e5b9ULL + static_cast<std::uint64_t>(g) + 1);
  std::vector<double> wander_period(base.size(), 1.0), wander_phase(base.size(), 0.0);
  for (std::size_t b = 0; b < base.size(); ++b) {
    wander_period[b] = extra.uniform(3.0, 8.0) * 144.0;
    wander_phase[b] = extra.uniform(0.0, 2.0 * M_PI);
  }
  std::vector<int> excursion_channel(rows, -1);
  std::vector<double> excursion_factor(rows, 1.0);
  for (int k = 0; k < o.short_excursions; ++k) {
    const std::size_t span = (spike_end - 200) / static_cast<std::size_t>(o.short_excursions);
    const std::size_t r0 = extra.index(200 + static_cast<std::size_t>(k) * span, 200 + static_cast<std::size_t>(k + 1) * span - 4);
    const int c = static_cast<int>(extra.index(0, static_cast<std::size_t>(g)));
    const double f = extra.uniform(1.15, 1.25);
    const std::size_t len = extra.index(2, 5);
    for (std::size_t r = r0; r < r0 + len && r < spike_end; ++r) {
      excursion_channel[r] = c;
      excursion_factor[r] = f;
    }
  }

  Ar1 load{0.99, 0.01};
  std::vector<Ar1> wander(base.size(), Ar1{0.97, 0.007}), noise(static_cast<std::size_t>(g), Ar1{0.3, 0.012});
  std::int64_t t_ns = kT0;
  std::size_t next_gap = 0;
  for (std::size_t t = 0; t < rows; ++t) {
    if (next_gap < 3 && t == gap_rows[next_gap]) t_ns += gap_ns[next_gap++];
    v.time_ns.push_back(t_ns);
    v.source_row.push_back(t);
    t_ns += 10 * kMinute;
    const double shared = load.next(d);
    const double day = std::sin(2.0 * M_PI * static_cast<double>(t) / 144.0 + phase);
    for (int b = 0; b < o.bearings; ++b) {
      const auto bi = static_cast<std::size_t>(b);
      const double own = wander[bi].next(d);
      const double fault = o.fault && b == 0
                               ? fault_log_rise(static_cast<double>(t) - static_cast<double>(o.fault_start),
                                                static_cast<double>(o.fault_rows_to_x4))
                               : 0.0;
      const double level = base[bi] + drift[bi] * static_cast<double>(t) / static_cast<double>(rows) + amp[bi] * day +
                           shared + own + fault +
                           o.slow_wander * std::sin(2.0 * M_PI * static_cast<double>(t) / wander_period[bi] + wander_phase[bi]);
      for (int s = 0; s < o.sensors_per_bearing; ++s) {
        const int c = b * o.sensors_per_bearing + s;
        double x = level + noise[static_cast<std::size_t>(c)].next(d);
        for (const auto& [row, lf] : steps[static_cast<std::size_t>(c)]) x += t >= row ? lf : 0.0;
        if (spike_channel[t] == c) x += std::log(spike_factor[t]);
        if (excursion_channel[t] == c) x += std::log(excursion_factor[t]);
        v.values(static_cast<Eigen::Index>(t), c) = std::exp(x);
      }
    }
  }
  char text[256];
  std::snprintf(text, sizeof text,
                "%zu rows x %d channels: drift, daily cycle, gaps at rows %zu/%zu/%zu (+15-20 %%), single-bearing steps at "
                "%zu/%zu (+20-40 %%), 1 spike/day%s%s",
                rows, g, gap_rows[0], gap_rows[1], gap_rows[2], step_rows[0], step_rows[1],
                o.fault ? ", accelerating fault of bearing 1" : "",
                o.slow_wander > 0.0 || o.short_excursions > 0 ? ", slow wander and short excursions" : "");
  v.description = text;
  return v;
}

}  // namespace causal::testing
