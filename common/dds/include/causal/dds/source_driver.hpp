// The one driver of every SampleSource (sample_source.hpp). run() waits for the readers, then publishes what the
// source gives until it ends or stop(), then waits (bounded) until the readers acknowledged everything.
// Exit codes (causal/config/exit_codes.hpp): 0 done or stopped, 1 bad input (or, with lost_is_fatal, a write the
// readers did not take), 3 the readers did not come in time, 4 a write lost or input refused.
#pragma once

#include "causal/dds/participant.hpp"
#include "causal/dds/sample_source.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

namespace CLI {
class App;
}

namespace causal::dds {

// Which readers a source waits for before publishing: --wait-subscribers, --wait-for, --wait-timeout.
struct SourceWaitOptions {
  int wait_subscribers = 1;           // matched readers (any) before publishing
  std::vector<std::string> wait_for;  // and readers of these participants ("causal-estimator[:N]")
  double wait_timeout_s = 30.0;       // 0 = for as long as it takes
};

// Registers the three options on a source's command line (one text for every source); `pauses`: the source
// also pauses whenever the --wait-for readers go away (SourceDriverOptions::pause_when_readers_go).
void add_source_wait_options(CLI::App& app, SourceWaitOptions& options, bool pauses);
// Registers --wait-for (refusing a malformed NAME[:COUNT] as a usage error) on any service that waits for the
// readers of its output: `what` says which readers and when, `example` the value of an example.
void add_wait_for_option(CLI::App& app, std::vector<std::string>& wait_for, const std::string& what,
                         const std::string& example);

struct SourceDriverOptions {
  SourceWaitOptions wait;
  bool frames = false;      // publishes causal_twin/vibration_frame
  bool conditions = false;  // publishes causal_twin/condition_input (with frames: its readers waited for before
                            // the first condition vector, a warning when they do not come)
  // Before every block, at least one reader (and one of every --wait-for name) must be matched; none means
  // pause until it is back (a restarting estimator), bounded by --wait-timeout.
  bool pause_when_readers_go = false;
  // Participant names whose new readers make restarted() answer (a restarted estimator); empty: never.
  std::vector<std::string> restart_readers;
  double write_timeout_s = 60.0;  // a write the readers do not accept within this is lost
  bool lost_is_fatal = false;     // a lost write ends the run with exit 1 (a replay: nothing may be skipped)
  // A live source publishes what it already took after a stop (a write then refused counts as lost); the
  // others end at the stop (and at the runtime bound) without counting the write it interrupted.
  bool drain_after_stop = false;
  double max_runtime_s = 0.0;     // stop after this many seconds in any case (0 = no bound)
};

class SourceDriver {
 public:
  SourceDriver(Participant& participant, SourceDriverOptions options);
  ~SourceDriver();
  int run(SampleSource& source);
  void stop();

  // For the source, inside next(): sleeps until `due_s` seconds after the first call (the start of
  // publishing) or the runtime bound. False when stopped meanwhile.
  bool pace(double due_s);
  // For the source, at a point where it can go back: the estimators' last published snapshots when a new reader
  // of `restart_readers` appeared since the last call (and every such reader is matched), else nullopt.
  std::optional<PublishedSnapshots> restarted();
  // After going back to snapshot `snapshot` of `group`: its frames get the sample indices they had the first time
  // (the sequence numbers go on). False when that snapshot was never numbered here.
  bool renumber_from(const std::string& group, std::uint64_t snapshot);
  bool stopping() const { return stop_.load(); }
  const std::atomic<bool>& stop_flag() const { return stop_; }
  int domain_id() const { return participant_.domain_id(); }
  double elapsed_s() const;

 private:
  struct Stream {  // one asset group's frame numbering
    std::uint64_t sequence = 0;
    std::uint64_t sample_index = 0;
    std::unordered_map<std::uint64_t, std::uint64_t> snapshot_start;  // snapshot -> its first sample index
  };
  using Clock = std::chrono::steady_clock;

  template <typename Writer>
  bool readers_present(const Writer& writer, bool first);
  bool primary_readers_present(bool first);
  void wait_for_condition_readers();
  // Writes one block; false when the run must end (stopped, runtime bound, a fatal loss).
  bool publish(SampleSource& source, SourceBlock& block);
  // The one place a frame is built from a block (frame layout changes land here).
  void build_frame(SourceBlock& block);
  Clock::time_point write_deadline() const;
  void log_lost(const SourceBlock& block, WriteResult result, int error) const;
  int finish(SampleSource& source, int code);

  Participant& participant_;
  SourceDriverOptions options_;
  std::vector<NamedReaders> wanted_;
  std::unique_ptr<TypedWriter<causal_twin::VibrationFramePubSubType>> frames_;
  std::unique_ptr<TypedWriter<causal_twin::ConditionVectorPubSubType>> conditions_;
  std::unique_ptr<TypedReader<causal_twin::ConditionVectorPubSubType>> progress_;  // the estimators' output
  causal_twin::VibrationFrame frame_;
  causal_twin::ConditionVector condition_;
  std::unordered_map<std::string, Stream> streams_;
  PublishedSnapshots published_;
  std::set<eprosima::fastrtps::rtps::GUID_t> known_readers_, new_readers_;
  Clock::time_point last_look_{};
  bool condition_readers_waited_ = false;
  bool readers_missing_ = false;
  bool fatal_ = false;
  SourceCounts counts_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  Clock::time_point started_;
  std::optional<Clock::time_point> origin_;  // the first pace() call
  Clock::time_point deadline_ = Clock::time_point::max();
};

}  // namespace causal::dds
