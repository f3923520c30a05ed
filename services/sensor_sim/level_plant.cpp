#include "level_plant.hpp"

#include "seed_mix.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace causal::sim {

namespace {

constexpr int kCausalOrder[LevelPlant::kChannels] = {1, 0, 2};  // channel 2 before channel 1 (A0(0, 1) != 0)

// The plant's own rise: 0 before kChangeAt, then a 20-snapshot ramp to 1.
double ramp(std::uint64_t n) {
  if (n < LevelPlant::kChangeAt) return 0.0;
  return std::min(1.0, static_cast<double>(n - LevelPlant::kChangeAt + 1) / 20.0);
}

}  // namespace

const char* to_string(PlantKind kind) {
  switch (kind) {
    case PlantKind::lever: return "lever";
    case PlantKind::no_lever: return "no-lever";
    case PlantKind::near_unit_root: return "near-unit-root";
  }
  return "?";
}

PlantKind plant_kind_from(const std::string& text) {
  for (PlantKind k : {PlantKind::lever, PlantKind::no_lever, PlantKind::near_unit_root}) {
    if (text == to_string(k)) return k;
  }
  throw std::invalid_argument("unknown plant '" + text + "' (lever, no-lever, near-unit-root)");
}

LevelPlant::LevelPlant(PlantKind kind, std::uint64_t seed, std::uint64_t group)
    : kind_(kind), rng_(mix(mix(seed) ^ group)), base_(std::log(0.08), std::log(0.10), std::log(0.06)) {
  // Self-lags: channel 1 0.3, channel 2 0.5 (0.95 near a unit root: a slow, wandering lever), channel 3 0.4.
  a1_(0, 0) = 0.3;
  a1_(1, 1) = kind == PlantKind::near_unit_root ? 0.95 : 0.5;
  a1_(2, 2) = 0.4;
  if (kind != PlantKind::no_lever) {
    a0_(0, 1) = 0.8;  // steady-state elasticity of channel 1 on channel 2: (0.8 + 0.2) / (1 - 0.3) = 1.43
    a1_(0, 1) = 0.2;
  }
}

double LevelPlant::noise() {
  // [0, 1) from the top 53 bits (portable, unlike std::uniform_real_distribution), mapped to [-0.035, 0.035).
  const double u = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
  return 0.035 * (2.0 * u - 1.0);
}

double LevelPlant::drift(int k, std::uint64_t n) const {
  // Channel 2's own rise, +0.5 in log at steady state ((1 - a) 0.5 / (1 - a)); in the no-lever plant channel 1 also
  // rises on its own by +0.5 (0.35 / (1 - 0.3)).
  if (k == 1) return (1.0 - a1_(1, 1)) * 0.5 * ramp(n);
  if (k == 0 && kind_ == PlantKind::no_lever) return 0.35 * ramp(n);
  return 0.0;
}

std::string LevelPlant::add(const LevelIntervention& iv) {
  if (iv.channel < 0 || iv.channel >= kChannels) return "channel " + std::to_string(iv.channel + 1) + " is not 1..3";
  if (!std::isfinite(iv.change_percent) || iv.change_percent <= -100.0) return "change must be finite and > -100 %";
  if (iv.duration == 0) return "duration must be at least 1 snapshot";
  if (iv.start < n_) {
    return "starts at snapshot " + std::to_string(iv.start) + " but snapshot " + std::to_string(n_ - 1) +
           " is already published (late)";
  }
  for (const auto& other : interventions_) {
    const bool overlap = iv.start < other.start + other.duration && other.start < iv.start + iv.duration;
    if (overlap && other.channel == iv.channel) {
      return "overlaps the intervention on the same channel from snapshot " + std::to_string(other.start);
    }
  }
  interventions_.push_back(iv);
  return {};
}

Eigen::VectorXd LevelPlant::next() {
  Eigen::Vector3d e;
  for (int k = 0; k < kChannels; ++k) e[k] = noise();  // drawn in channel order: the stream never depends on do()
  const Eigen::Vector3d z_prev = z_, z0_prev = z0_;
  for (int k : kCausalOrder) {
    z0_[k] = a0_.row(k).dot(z0_) + a1_.row(k).dot(z0_prev) + drift(k, n_) + e[k];
    z_[k] = a0_.row(k).dot(z_) + a1_.row(k).dot(z_prev) + drift(k, n_) + e[k];
    for (const auto& iv : interventions_) {
      if (iv.channel == k && n_ >= iv.start && n_ - iv.start < iv.duration) {
        z_[k] = z0_[k] + std::log1p(iv.change_percent / 100.0);  // (P2): equation k replaced
      }
    }
  }
  effect_ = z_ - z0_;
  ++n_;
  return (base_ + z_).array().exp().matrix();
}

std::string LevelPlant::describe() const {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%s plant: log levels z1 = %+.2f z2 %+.2f z2[n-1] %+.2f z1[n-1], z2 = %+.2f z2[n-1] + own rise from "
                "snapshot %llu, z3 = %+.2f z3[n-1]%s; uniform noise sd 0.02",
                to_string(kind_), a0_(0, 1), a1_(0, 1), a1_(0, 0), a1_(1, 1),
                static_cast<unsigned long long>(kChangeAt), a1_(2, 2),
                kind_ == PlantKind::no_lever ? "; z1 rises on its own too" : "");
  return buf;
}

}  // namespace causal::sim
