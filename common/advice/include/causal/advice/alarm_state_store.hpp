// Crash and restart safety of alarm-recommender (--state-dir DIR). One checkpoint per alarm engine (asset
// group and time scale): DIR/<sanitised asset group>.<condition|sample>.alarms.state, holding the engine
// (baselines, detectors, alarm id counters, active alarms), the last observation index it processed and
// the last published event of every alarm id, then the asset group's prognosis trends (causal_prognosis
// ChannelTrends; a checkpoint written before they existed ends after the engine and resumes with new trends). Without it a kill -9 meant: baseline re-learned on possibly
// faulty data, alarm ids reused, and alarms raised before the crash invisible to readers that join later.
//
// Order per observation (see AlarmDesk::judge, alarm_desk.hpp): is_duplicate() -> engine.observe() -> record()
// (checkpoint written) -> publish. The checkpoint is written BEFORE the events are published, so an event
// that reached a reader is always in the checkpoint; one saved but not yet published when the process died
// is published at restart with the others (republish list of open()).
//
// Files are written atomically (causal::estimation::save_state_file: temporary file + rename), so a kill -9 while
// saving leaves the previous checkpoint. Not fsync'ed: survives a process crash, not a power loss.
#pragma once

#include "causal/alarms/alarm_engine.hpp"
#include "causal/prognosis/channel_trends.hpp"

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace causal::advice {

class AlarmStateStore {
 public:
  using Clock = std::chrono::steady_clock;

  // state_dir empty: no persistence (duplicate detection still works within the process). Otherwise the
  // directory is created if needed; throws std::invalid_argument when it cannot be.
  // sample_level_interval: at sample level (tens of observations per second) the checkpoint is written at
  // most this often, and at once after an observation that raised, escalated or cleared an alarm.
  explicit AlarmStateStore(std::string state_dir,
                           std::chrono::milliseconds sample_level_interval = std::chrono::milliseconds(1000));
  AlarmStateStore(const AlarmStateStore&) = delete;
  AlarmStateStore& operator=(const AlarmStateStore&) = delete;

  bool enabled() const { return !dir_.empty(); }
  // File name part of an asset group: letters, digits, '.', '-', '_' kept, anything else '_'; when anything
  // was replaced, "-" and 8 hex digits of a hash of the original follow, so two groups never share a file.
  static std::string sanitise(const std::string& asset_group);
  std::string path(const std::string& asset_group, bool sample_level) const;

  struct Opened {
    std::unique_ptr<alarms::AlarmEngine> engine;
    std::unique_ptr<prognosis::ChannelTrends> trends;  // the group's degradation trends (restored or new)
    bool resumed = false;                        // restored from a checkpoint
    std::vector<alarms::AlarmEvent> republish;   // last published event of every alarm id (when resumed)
  };
  // The engine of a stream seen for the first time: restored from its checkpoint when there is one, else
  // new. Throws estimation::StateError naming the file when a checkpoint exists but cannot be used (corrupted,
  // truncated, other alarm parameters, other channels or factors): restarting silently would re-learn the
  // baseline and reuse alarm ids, so the operator decides (move the file away to start over).
  Opened open(const std::string& asset_group, bool sample_level, const std::vector<std::string>& channel_names,
              const std::vector<std::string>& factor_names, const alarms::AlarmParams& params,
              const prognosis::PrognosisParams& prognosis_params = prognosis::PrognosisParams{});
  // The last observation index the stream's engine processed (nullopt: none yet).
  std::optional<std::uint64_t> last_index(const std::string& asset_group, bool sample_level) const;

  // Every checkpoint in the state directory (asset group and time scale, read from the file itself: the file
  // name is sanitised). The service restores them at start, before any data arrives, so the alarms raised
  // before a restart reach readers that join after it even when no new data comes (a source that finished).
  struct Found {
    std::string asset_group;
    bool sample_level = false;
  };
  std::vector<Found> checkpoints() const;
  // open() of a stream not seen yet: the checkpoint's own channel and factor names are taken; the caller
  // compares them with the stream's when its first observation arrives (same refusal as open()).
  Opened open_checkpoint(const std::string& asset_group, bool sample_level, const alarms::AlarmParams& params,
                         const prognosis::PrognosisParams& prognosis_params = prognosis::PrognosisParams{});

  // True (and counted) when `index` is not after the last index the stream's engine processed: a re-sent
  // observation (e.g. an estimator that resumed from an older checkpoint of its own). Call after open().
  bool is_duplicate(const std::string& asset_group, bool sample_level, std::uint64_t index);
  // After the engine processed observation `index` and produced `events`: remembers the events (last per
  // alarm id) and writes the checkpoint (condition level: every time; sample level: see the constructor).
  // A failed write is counted and reported (take_errors), never thrown: alarms keep flowing when the disk is full.
  void record(const std::string& asset_group, bool sample_level, std::uint64_t index,
              const std::vector<alarms::AlarmEvent>& events);
  // Writes every checkpoint with changes not yet written (sample-level throttling); call at exit.
  void flush();

  // The failed writes to log since the last call: the first and then every 100th, so a full disk does not flood
  // the log ("checkpoint not written (N failures so far): why"). The store has no logger: the service logs them.
  std::vector<std::string> take_errors() { return std::exchange(errors_, {}); }

  std::uint64_t duplicates() const { return duplicates_; }
  std::uint64_t saves() const { return saves_; }
  std::uint64_t save_failures() const { return save_failures_; }

 private:
  struct Stream {
    const alarms::AlarmEngine* engine = nullptr;  // owned by the caller (open() handed it out)
    const prognosis::ChannelTrends* trends = nullptr;  // likewise
    std::optional<std::uint64_t> last_index;
    std::map<std::string, alarms::AlarmEvent> last_events;  // by alarm id
    bool unsaved = false;
    std::optional<Clock::time_point> last_save;
  };
  using Key = std::pair<std::string, bool>;
  void save(const Key& key, Stream& s);
  // open()'s body; null names: the checkpoint's (open_checkpoint).
  Opened open_stream(const std::string& asset_group, bool sample_level, const std::vector<std::string>* channel_names,
                     const std::vector<std::string>* factor_names, const alarms::AlarmParams& params,
                     const prognosis::PrognosisParams& prognosis_params);

  std::string dir_;
  std::chrono::milliseconds sample_interval_;
  std::map<Key, Stream> streams_;
  std::uint64_t duplicates_ = 0, saves_ = 0, save_failures_ = 0;
  std::vector<std::string> errors_;
};

}  // namespace causal::advice
