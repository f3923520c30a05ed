// Liveliness and deadlines of the sources a service consumes ("nothing stalls"): one entry per source (an
// asset group's input stream), fed with what the DDS reader saw, checked against the clock. It decides when
// a source is silent and when it is back; the service turns the changes into HEALTH alarms and log lines.
//  * data arrived                 -> healthy; an open alarm clears;
//  * the writer ended it cleanly  -> not a fault (its participant left cleanly): no alarm, an open one clears;
//  * the writer was lost          -> alarm at once (NOT_ALIVE_NO_WRITERS: a killed or disconnected source);
//  * no data for deadline_s       -> alarm, while the writer is still alive (a stalled source).
// Standard library only, and the clock is passed in, so the logic is tested with a fake clock.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace causal::dds {

struct HealthChange {
  enum class Kind { Raised, Cleared };
  Kind kind = Kind::Raised;
  std::string source;
  std::string reason;                // what is silent and since when (or why it cleared)
  bool has_index = false;            // an index (snapshot) was seen from this source
  std::uint64_t last_index = 0;      // the last one seen (the alarm id names it)
  double silent_s = 0.0;             // seconds since the last data at the time of the change
};

class SourceHealth {
 public:
  using Clock = std::chrono::steady_clock;
  // deadline_s: longest allowed silence of a live source (0 = no deadline: only lost writers raise).
  // Negative or non-finite values are refused (std::invalid_argument).
  explicit SourceHealth(double deadline_s);

  // Data of `source` arrived at `now`, with its source index when it has one.
  void on_data(const std::string& source, Clock::time_point now, std::vector<HealthChange>& out);
  void on_data(const std::string& source, std::uint64_t index, Clock::time_point now, std::vector<HealthChange>& out);
  // The source ended cleanly (its writer left saying goodbye, or disposed the instance).
  void on_ended(const std::string& source, Clock::time_point now, std::vector<HealthChange>& out);
  // Every writer of the source left without ending it (killed, lease expired, disconnected).
  void on_writer_lost(const std::string& source, Clock::time_point now, std::vector<HealthChange>& out);
  // Raises the deadline alarms that are due at `now`. Call it regularly (the run loop wakes at least every 200 ms).
  void check(Clock::time_point now, std::vector<HealthChange>& out);

  double deadline_s() const { return deadline_s_; }
  std::size_t sources() const { return sources_.size(); }
  std::size_t active_alarms() const;
  std::uint64_t raised() const { return raised_; }
  std::uint64_t cleared() const { return cleared_; }

 private:
  enum class State { Alive, Ended, Lost };
  struct Source {
    State state = State::Alive;
    Clock::time_point last_data{};
    bool has_data = false;
    bool has_index = false;
    std::uint64_t last_index = 0;
    bool alarmed = false;
  };
  // A change of source s (its name, index and silence now); the caller adds the reason.
  static HealthChange change(HealthChange::Kind kind, const std::string& name, const Source& s, Clock::time_point now);
  void raise(const std::string& name, Source& s, Clock::time_point now, const std::string& what,
             std::vector<HealthChange>& out);
  void clear(const std::string& name, Source& s, Clock::time_point now, const std::string& why,
             std::vector<HealthChange>& out);

  double deadline_s_;
  std::map<std::string, Source> sources_;
  std::uint64_t raised_ = 0, cleared_ = 0;
};

}  // namespace causal::dds
