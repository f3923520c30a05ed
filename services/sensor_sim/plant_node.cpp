#include "plant_node.hpp"

#include "sim_node.hpp"

#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>

namespace causal::sim {

namespace {
std::string group_id(const std::string& prefix, int index) { return fmt::format("{}{:04d}", prefix, index); }
}  // namespace

PlantNode::PlantNode(SimOptions options)
    : options_(std::move(options)),
      participant_(dds::to_dds_settings(options_.dds, "sensor-sim")),
      driver_(participant_, driver_options(options_, false)),
      interventions_(participant_) {
  for (int c = 1; c <= LevelPlant::kChannels; ++c) channel_names_.push_back("ch" + std::to_string(c));
  for (int i = 0; i < options_.groups; ++i) {
    // Plant kinds cycle over the groups: --plant lever,no-lever gives sim-0000 lever, sim-0001 no-lever, ...
    const PlantKind kind = plant_kind_from(options_.plants[static_cast<std::size_t>(i) % options_.plants.size()]);
    groups_.push_back(Group{group_id(options_.group_prefix, i), LevelPlant(kind, options_.seed, static_cast<std::uint64_t>(i))});
    spdlog::info("{}: {}", groups_.back().id, groups_.back().plant.describe());
  }
}

void PlantNode::apply(const causal_twin::Intervention& in) {
  if (!seen_requests_.insert(in.request_id()).second) return;  // the same approval delivered again
  auto it = std::find_if(groups_.begin(), groups_.end(), [&](const Group& g) { return g.id == in.asset_group(); });
  if (it == groups_.end()) {
    ++other_groups_;
    spdlog::debug("intervention {} is for asset group '{}', not simulated here", in.request_id(), in.asset_group());
    return;
  }
  LevelIntervention iv;
  iv.channel = static_cast<int>(in.channel()) - 1;
  iv.change_percent = in.change_percent();
  iv.start = in.start_snapshot_index();
  iv.duration = in.duration_snapshots();
  const std::string why = it->plant.add(iv);
  if (!why.empty()) {
    ++refused_;
    spdlog::error("{}: intervention {} (approved by {}) refused: {}", in.asset_group(), in.request_id(),
                  in.approved_by(), why);
    return;
  }
  ++applied_;
  spdlog::info("{}: intervention {} approved by {}: channel {} level {:+.1f} % for snapshots {}..{} (answers {})",
               in.asset_group(), in.request_id(), in.approved_by(), in.channel(), in.change_percent(),
               iv.start, iv.start + iv.duration - 1, in.recommendation_id().empty() ? "-" : in.recommendation_id());
}

void PlantNode::take_interventions() {
  const auto ours = [this](const std::string& group) {
    return std::any_of(groups_.begin(), groups_.end(), [&](const Group& g) { return g.id == group; });
  };
  interventions_.take(ours, [this](const causal_twin::Intervention& in) { apply(in); });
}

dds::Take PlantNode::end() {
  if (!ended_) take_interventions();  // counted even when it came after the last snapshot (then refused as late)
  ended_ = true;
  return dds::Take::End;
}

dds::Take PlantNode::next(dds::SourceDriver& driver, dds::SourceBlock& out) {
  if (next_group_ == groups_.size()) {
    next_group_ = 0;
    ++snapshot_;
  }
  if (driver.stopping() || snapshot_ >= options_.snapshots) return end();
  const std::uint64_t n = snapshot_;
  if (next_group_ == 0) {
    if (n == 0) {
      spdlog::info("publishing {} simulated plant(s), {} snapshots each{}", groups_.size(), options_.snapshots,
                   options_.snapshot_rate > 0 ? fmt::format(", {} snapshots/s", options_.snapshot_rate) : std::string());
    }
    if (options_.snapshot_rate > 0 && !driver.pace(static_cast<double>(n) / options_.snapshot_rate)) return end();
    take_interventions();  // before every snapshot: an approval for it applies from its start index
  }
  auto& g = groups_[next_group_++];
  out.kind = dds::SourceBlock::Kind::Condition;
  out.condition.asset_group = g.id;
  out.condition.feature = options_.plant_feature;
  out.condition.channel_names = channel_names_;
  out.condition.snapshot_index = n;
  out.condition.time_ns = options_.start_time_ns + static_cast<std::int64_t>(n) * options_.snapshot_seconds * 1000000000LL;
  out.condition.discontinuity = (n == 0);
  out.values = g.plant.next();
  if (g.plant.true_effect().cwiseAbs().maxCoeff() > 0.0) {
    spdlog::debug("{} snapshot {}: true effect of the interventions (log level) {:+.4f} {:+.4f} {:+.4f}", g.id, n,
                  g.plant.true_effect()[0], g.plant.true_effect()[1], g.plant.true_effect()[2]);
  }
  return dds::Take::Block;
}

void PlantNode::summary(const dds::SourceCounts& counts, bool) const {
  std::printf("sensor-sim: sent snapshots=%llu groups=%zu lost=%llu interventions applied=%llu refused=%llu "
              "other_groups=%llu not_entitled=%llu\n",
              static_cast<unsigned long long>(counts.conditions), groups_.size(),
              static_cast<unsigned long long>(counts.lost), static_cast<unsigned long long>(applied_),
              static_cast<unsigned long long>(refused_), static_cast<unsigned long long>(other_groups_),
              static_cast<unsigned long long>(interventions_.not_entitled()));
  std::fflush(stdout);
}

}  // namespace causal::sim
