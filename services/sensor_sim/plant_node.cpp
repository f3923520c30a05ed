#include "plant_node.hpp"

#include "causal/dds/frame_conversions.hpp"
#include "causal/config/exit_codes.hpp"
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
      conditions_(participant_, dds::topics::kConditionInput, dds::profiles::kConditionInputWriter),
      interventions_(participant_) {
  for (int c = 1; c <= LevelPlant::kChannels; ++c) channel_names_.push_back("ch" + std::to_string(c));
  for (int i = 0; i < options_.groups; ++i) {
    // Plant kinds cycle over the groups: --plant lever,no-lever gives sim-0000 lever, sim-0001 no-lever, ...
    const PlantKind kind = plant_kind_from(options_.plants[static_cast<std::size_t>(i) % options_.plants.size()]);
    groups_.push_back(Group{group_id(options_.group_prefix, i), LevelPlant(kind, options_.seed, static_cast<std::uint64_t>(i))});
    spdlog::info("{}: {}", groups_.back().id, groups_.back().plant.describe());
  }
}

void PlantNode::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_all();
}

bool PlantNode::sleep_until(Clock::time_point due) {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait_until(lock, due, [this] { return stop_.load(); });
  return !stop_.load();
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

bool PlantNode::publish_snapshot(std::uint64_t n) {
  causal_twin::ConditionVector out;
  dds::ConditionHeader header;
  header.feature = options_.plant_feature;
  header.channel_names = channel_names_;
  header.snapshot_index = n;
  header.time_ns = options_.start_time_ns + static_cast<std::int64_t>(n) * options_.snapshot_seconds * 1000000000LL;
  header.discontinuity = (n == 0);
  for (auto& g : groups_) {
    header.asset_group = g.id;
    const Eigen::VectorXd levels = g.plant.next();
    if (g.plant.true_effect().cwiseAbs().maxCoeff() > 0.0) {
      spdlog::debug("{} snapshot {}: true effect of the interventions (log level) {:+.4f} {:+.4f} {:+.4f}", g.id, n,
                    g.plant.true_effect()[0], g.plant.true_effect()[1], g.plant.true_effect()[2]);
    }
    dds::to_condition_vector(header, levels, out);
    const auto result = conditions_.write(out, stop_);
    if (result == dds::WriteResult::Stopped) return false;
    if (result != dds::WriteResult::Ok) {
      ++lost_;
      spdlog::error("{}: snapshot {} lost: readers stopped acknowledging", g.id, n);
      continue;
    }
    ++sent_;
  }
  return true;
}

int PlantNode::run() {
  if (options_.wait_subscribers > 0) {
    const auto wait = std::chrono::milliseconds(static_cast<long>(options_.wait_timeout_s * 1000.0));
    if (!conditions_.wait_for_readers(static_cast<std::size_t>(options_.wait_subscribers), wait, stop_)) {
      print_summary();
      if (stop_.load()) return config::kExitOk;
      spdlog::error("no reader of condition inputs matched within {:.0f} s", options_.wait_timeout_s);
      return config::kExitNoPeer;
    }
  }
  spdlog::info("publishing {} simulated plant(s), {} snapshots each{}", groups_.size(), options_.snapshots,
               options_.snapshot_rate > 0 ? fmt::format(", {} snapshots/s", options_.snapshot_rate) : std::string());
  const auto origin = Clock::now();
  for (std::uint64_t n = 0; n < options_.snapshots; ++n) {
    if (options_.snapshot_rate > 0) {
      const auto due = origin + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(static_cast<double>(n) / options_.snapshot_rate));
      if (!sleep_until(due)) break;
    }
    take_interventions();
    if (!publish_snapshot(n)) break;
  }
  take_interventions();  // counted even when it came after the last snapshot (then refused as late)
  if (!conditions_.wait_for_acknowledgments(std::chrono::seconds(stop_.load() ? 2 : 30))) {
    spdlog::warn("not every condition vector was acknowledged by the readers");
  }
  print_summary();
  // A refused approval (late, overlapping, or from a writer not entitled to its group) is a refusal like a lost
  // snapshot: the summary says which.
  return lost_ + refused_ + interventions_.not_entitled() > 0 ? config::kExitLostOrRefused : config::kExitOk;
}

void PlantNode::print_summary() const {
  std::printf("sensor-sim: sent snapshots=%llu groups=%zu lost=%llu interventions applied=%llu refused=%llu "
              "other_groups=%llu not_entitled=%llu\n",
              static_cast<unsigned long long>(sent_), groups_.size(), static_cast<unsigned long long>(lost_),
              static_cast<unsigned long long>(applied_), static_cast<unsigned long long>(refused_),
              static_cast<unsigned long long>(other_groups_),
              static_cast<unsigned long long>(interventions_.not_entitled()));
  std::fflush(stdout);
}

}  // namespace causal::sim
