// A simulated plant at the condition level, for the closed prescriptive loop: one condition feature per channel
// and snapshot, whose log levels z follow a structural VAR(1) with a known answer,
//
//     z[n] = A0 z[n] + A1 z[n-1] + c[n] + e[n],      level_k[n] = base_k exp(z_k[n]),                 (P1)
//
// A0 acyclic (channel 2 -> channel 1: the equations are solved in the causal order 2, 1, 3, plain substitution),
// A1 with self-lags, c[n] the plant's own drift (a bearing's own rise), e uniform noise (non-Gaussian:
// VAR-LiNGAM can order it).
//
// An approved intervention is the do-operation the twin's what-if assumes (common/analysis/intervention.hpp,
// (W1)): for n in [start, start + duration) equation j is replaced by
//     z_j[n] := z_j^0[n] + delta,      delta = log(1 + change_percent / 100),                         (P2)
// where z^0 is the plant WITHOUT the intervention, driven by the same noise; every other equation is kept, so
// the change propagates through A0 and A1 and, after the window, decays through the plant's own dynamics. The
// plant without the intervention is simulated alongside (same noise draws), so the true effect z - z^0 of every
// intervention is known exactly. Everything is a function of (kind, seed, the interventions and their snapshot
// indices): the same input gives the same output, whatever the pacing. Eigen and the standard library only.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace causal::sim {

// lever: channel 2 drives channel 1 (0.8 at once, 0.2 lagged); from the change snapshot channel 2's own level
//   rises (+0.5 in log, a 20-snapshot ramp), channel 1 follows through the link: cutting channel 2 helps.
// no_lever: channels unlinked; channels 1 and 2 both rise on their own: no channel is a lever for channel 1.
// near_unit_root: the lever plant with channel 2's self-lag at 0.95 (a slow, barely stable lever: the twin's
//   model sits near a unit root, so its what-if answers are horizons, not steady states).
enum class PlantKind { lever, no_lever, near_unit_root };
const char* to_string(PlantKind kind);
// "lever", "no-lever", "near-unit-root"; throws std::invalid_argument naming the accepted values.
PlantKind plant_kind_from(const std::string& text);

struct LevelIntervention {
  int channel = 0;                   // 0-based j
  double change_percent = 0.0;       // > -100
  std::uint64_t start = 0;           // first snapshot index it applies to
  std::uint64_t duration = 0;        // snapshots (> 0)
};

class LevelPlant {
 public:
  static constexpr int kChannels = 3;
  static constexpr std::uint64_t kChangeAt = 250;  // snapshot from which the plant's own rise starts

  LevelPlant(PlantKind kind, std::uint64_t seed, std::uint64_t group);

  // Levels (base exp z) of snapshot `next_index()`, then advances. Interventions with start < next_index() can
  // no longer be applied as asked: add() refuses them.
  Eigen::VectorXd next();
  std::uint64_t next_index() const { return n_; }

  // Schedules an intervention. Empty string when accepted, else why not (late start, bad channel or size, an
  // overlapping intervention on the same channel).
  std::string add(const LevelIntervention& intervention);
  const std::vector<LevelIntervention>& interventions() const { return interventions_; }

  // z - z^0 of the last snapshot returned by next(): the true effect of the interventions so far (log level).
  const Eigen::VectorXd& true_effect() const { return effect_; }
  // Matrices of (P1), for tests and the description logged at start.
  const Eigen::Matrix3d& a0() const { return a0_; }
  const Eigen::Matrix3d& a1() const { return a1_; }
  std::string describe() const;

 private:
  double drift(int k, std::uint64_t n) const;
  double noise();  // uniform, sd 0.02

  PlantKind kind_;
  std::mt19937_64 rng_;
  Eigen::Matrix3d a0_ = Eigen::Matrix3d::Zero(), a1_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d base_;
  Eigen::Vector3d z_ = Eigen::Vector3d::Zero(), z0_ = Eigen::Vector3d::Zero();  // with / without interventions
  Eigen::VectorXd effect_ = Eigen::VectorXd::Zero(kChannels);
  std::vector<LevelIntervention> interventions_;
  std::uint64_t n_ = 0;
};

}  // namespace causal::sim
