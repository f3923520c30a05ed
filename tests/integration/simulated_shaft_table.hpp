// A small simulated shaft for the alarm management tests (integration and browser): 400 snapshots of 4 bearings,
// log-levels of a structural VAR(1) (as in test_recommendation_upstream.cpp). From snapshot 250 bearing 2's own
// level rises and bearing 1 follows it, so alarms are raised on both (two open alarms of different sources at the
// end). Seeded: the same table every run of one seed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace causal::test {

inline constexpr int kSimulatedShaftSnapshots = 400;
inline constexpr int kSimulatedShaftChangeAt = 250;  // bearing 2's own level starts to rise here

// Writes DIR/simulated_features.csv (IMS layout: timestamp, bearing1..4) and returns its path. Log-levels of a
// structural VAR(1): z2 -> z1 instantaneous 0.8 and lagged 0.2; uniform (non-Gaussian) noise of sd 0.02.
inline std::string write_simulated_shaft_table(const std::filesystem::path& dir, std::uint64_t seed = 20261128) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.035, 0.035);
  const double base[4] = {std::log(0.08), std::log(0.10), std::log(0.06), std::log(0.05)};
  double z[4] = {0, 0, 0, 0}, prev[4] = {0, 0, 0, 0};
  const std::filesystem::path p = dir / "simulated_features.csv";
  std::ofstream out(p);
  out << ",bearing1,bearing2,bearing3,bearing4\n";
  for (int n = 0; n < kSimulatedShaftSnapshots; ++n) {
    const double own_change =
        n < kSimulatedShaftChangeAt ? 0.0 : 0.5 * std::min(1.0, (n - kSimulatedShaftChangeAt + 1) / 20.0);
    z[1] = 0.5 * prev[1] + u(rng) + own_change * 0.5;  // steady state of the shift: +own_change
    z[0] = 0.8 * z[1] + 0.2 * prev[1] + 0.3 * prev[0] + u(rng);
    z[2] = 0.4 * prev[2] + u(rng);
    z[3] = 0.4 * prev[3] + u(rng);
    std::copy(z, z + 4, prev);
    const long minutes = 10L * n;
    char ts[32];
    std::snprintf(ts, sizeof ts, "2026-01-%02ld %02ld:%02ld:00", 1 + minutes / 1440, (minutes / 60) % 24, minutes % 60);
    out << ts;
    for (int k = 0; k < 4; ++k) out << "," << std::exp(base[k] + z[k]);
    out << "\n";
  }
  return p.string();
}

}  // namespace causal::test
