// sensor-replay's two sources (dds::SampleSource; dds::SourceDriver does the DDS side): recorded raw snapshots
// (an IMS directory or a channel CSV) as vibration frames, and a per-snapshot feature table as condition vectors.
// Both go back to the snapshot after the last one the estimators published when a restarted estimator appears,
// so nothing it received but had not processed is lost (the estimator skips what its checkpoint holds).
#pragma once

#include "replay_options.hpp"
#include "snapshot_source.hpp"

#include "causal/dds/sample_source.hpp"
#include "causal/io/feature_table.hpp"

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace causal::replay {

// What both replays share: the snapshots to send (--first-snapshot, --max-snapshots) and where the replay is, the
// rewind for a restarted estimator, the pacing in plant time (--speed) and the progress lines (--progress-every).
class ReplaySource : public dds::SampleSource {
 protected:
  explicit ReplaySource(const ReplayOptions& options) : options_(options) {}
  // Sends snapshots first_ .. last_ - 1 of the `available` ones, from first_.
  void select(std::size_t available);
  // When a restarted estimator has appeared (driver.restarted()): next_ goes back to the snapshot after the last one
  // the estimators published, and true; false when nothing is to be sent again.
  bool rewound(dds::SourceDriver& driver);
  // Sleeps until plant time `plant_ns` is due at the configured speed. False if stopped meanwhile.
  bool pace(dds::SourceDriver& driver, std::int64_t plant_ns);
  // A progress line for `done` of the selected snapshots: every --progress-every seconds, or now when forced.
  void report_progress(std::size_t done, bool force) const;

  const ReplayOptions& options_;
  const dds::SourceDriver* driver_ = nullptr;  // set by start(); null: never started (no readers)
  std::size_t first_ = 0, last_ = 0, next_ = 0;  // next_: the snapshot loaded (or to load)
  std::uint64_t rewinds_ = 0;

 private:
  std::optional<std::int64_t> plant_origin_ns_;
  mutable std::chrono::steady_clock::time_point last_progress_ = std::chrono::steady_clock::now();
};

class SnapshotReplay final : public ReplaySource {
 public:
  explicit SnapshotReplay(const ReplayOptions& options) : ReplaySource(options) {}
  void start(dds::SourceDriver& driver) override;
  dds::Take next(dds::SourceDriver& driver, dds::SourceBlock& out) override;
  void written(const dds::SourceBlock& block, dds::WriteResult result, const causal_twin::VibrationFrame*) override;
  void summary(const dds::SourceCounts& counts, bool stopped) const override;

 private:
  std::unique_ptr<SnapshotSource> source_;
  dds::FrameHeader header_;
  bool loaded_ = false;
  Snapshot snapshot_;
  Eigen::Index row_ = 0;
  std::uint64_t samples_sent_ = 0, snapshots_sent_ = 0;
};

class FeatureTableReplay final : public ReplaySource {
 public:
  explicit FeatureTableReplay(const ReplayOptions& options) : ReplaySource(options) {}
  void start(dds::SourceDriver& driver) override;
  dds::Take next(dds::SourceDriver& driver, dds::SourceBlock& out) override;
  void written(const dds::SourceBlock& block, dds::WriteResult result, const causal_twin::VibrationFrame*) override;
  void summary(const dds::SourceCounts& counts, bool stopped) const override;

 private:
  std::vector<std::int64_t> time_ns_;
  Eigen::MatrixXd values_;
  std::vector<bool> after_gap_;
  std::size_t time_gaps_ = 0;
  dds::ConditionHeader header_;
  std::uint64_t sent_ = 0;
};

}  // namespace causal::replay
