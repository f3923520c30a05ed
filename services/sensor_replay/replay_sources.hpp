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

// Progress lines every --progress-every seconds, and the pacing in plant time (--speed).
class ReplayClock {
 public:
  explicit ReplayClock(const ReplayOptions& options) : options_(options) {}
  // Sleeps until plant time `plant_ns` is due at the configured speed. False if stopped meanwhile.
  bool pace(dds::SourceDriver& driver, std::int64_t plant_ns);
  void report_progress(const dds::SourceDriver& driver, std::size_t done, std::size_t total, bool force) const;

 private:
  const ReplayOptions& options_;
  std::optional<std::int64_t> plant_origin_ns_;
  mutable std::chrono::steady_clock::time_point last_progress_ = std::chrono::steady_clock::now();
};

// The first snapshot to send again for a restarted estimator of `group`, or nullopt (nothing to resend).
std::optional<std::size_t> rewind_point(const dds::PublishedSnapshots& published, const std::string& group,
                                        std::size_t first, std::size_t next, const std::vector<std::string>& who);

class SnapshotReplay final : public dds::SampleSource {
 public:
  explicit SnapshotReplay(const ReplayOptions& options) : options_(options), clock_(options) {}
  void start(dds::SourceDriver& driver) override;
  dds::Take next(dds::SourceDriver& driver, dds::SourceBlock& out) override;
  void written(const dds::SourceBlock& block, dds::WriteResult result, const causal_twin::VibrationFrame*) override;
  void summary(const dds::SourceCounts& counts, bool stopped) const override;

 private:
  const ReplayOptions& options_;
  ReplayClock clock_;
  const dds::SourceDriver* driver_ = nullptr;
  std::unique_ptr<SnapshotSource> source_;
  dds::FrameHeader header_;
  std::size_t first_ = 0, last_ = 0, next_ = 0;  // next_: the snapshot loaded (or to load)
  bool loaded_ = false;
  Snapshot snapshot_;
  Eigen::Index row_ = 0;
  std::uint64_t samples_sent_ = 0, snapshots_sent_ = 0, rewinds_ = 0;
};

class FeatureTableReplay final : public dds::SampleSource {
 public:
  explicit FeatureTableReplay(const ReplayOptions& options) : options_(options), clock_(options) {}
  void start(dds::SourceDriver& driver) override;
  dds::Take next(dds::SourceDriver& driver, dds::SourceBlock& out) override;
  void written(const dds::SourceBlock& block, dds::WriteResult result, const causal_twin::VibrationFrame*) override;
  void summary(const dds::SourceCounts& counts, bool stopped) const override;

 private:
  const ReplayOptions& options_;
  ReplayClock clock_;
  const dds::SourceDriver* driver_ = nullptr;
  std::vector<std::int64_t> time_ns_;
  Eigen::MatrixXd values_;
  std::vector<bool> after_gap_;
  std::size_t time_gaps_ = 0;
  dds::ConditionHeader header_;
  std::size_t first_ = 0, last_ = 0, next_ = 0;
  std::uint64_t sent_ = 0, rewinds_ = 0;
};

}  // namespace causal::replay
