// Input lost before the engine (input_continuity.hpp): the index steps, the HEALTH event naming the missing
// range, and its checkpoint section.
#include "input_continuity.hpp"

#include <string>
#include <utility>
#include <vector>

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"
#include "causal/io/time_format.hpp"
#include "engine_internal.hpp"

namespace causal::alarms {

namespace detail {

LostRange IndexContinuity::step(std::uint64_t index, std::int64_t time_ns) {
  LostRange r;
  if (has_last && index > last_index) {
    const std::uint64_t d = index - last_index;
    // Judged on the steps before this one: a loss must not vote for its own source being consecutive.
    if (d > 1 && unit_steps > other_steps) {
      r.count = d - 1;
      r.first = last_index + 1;
      r.last = index - 1;
      r.since_ns = last_time_ns;
      ++losses;
      lost += r.count;
    }
    ++(d == 1 ? unit_steps : other_steps);
  }
  has_last = true;
  last_index = index;
  last_time_ns = time_ns;
  return r;
}

// One field list for save and restore (state_fields.hpp): C is const when saving.
template <class IO, class C>
void continuity_fields(IO io, C& c) {
  io.tag("alarm_index_continuity", 1);
  io(c.has_last, c.last_index, c.last_time_ns, c.unit_steps, c.other_steps, c.losses, c.lost);
}

void save(estimation::StateWriter& out, const IndexContinuity& c) { continuity_fields(estimation::SaveFields{out}, c); }

void restore(estimation::StateReader& in, IndexContinuity& c) { continuity_fields(estimation::RestoreFields{in}, c); }

}  // namespace detail

void AlarmEngine::Impl::report_lost(const detail::LostRange& r, const Observation& obs, std::vector<AlarmEvent>& events) {
  AlarmEvent e;
  e.alarm_id = group + (id_scope.empty() ? "" : "/" + id_scope) + "/observations/" + kind::kInputLost + "/" +
               std::to_string(continuity.losses);
  e.channel = -1;  // the whole asset group
  e.severity = Severity::Warning;
  e.kind = kind::kInputLost;
  e.category = category::kHealth;
  e.state = AlarmState::Raised;
  e.raised_time_ns = obs.time_ns;
  e.index = obs.index;
  e.onset_index = r.first;
  e.onset_time_ns = r.since_ns;
  e.score = static_cast<double>(r.count);
  const std::string range = r.first == r.last ? "observation " + std::to_string(r.first)
                                              : "observations " + std::to_string(r.first) + ".." + std::to_string(r.last);
  e.reason = std::to_string(r.count) + (r.count == 1 ? " observation" : " observations") +
             " never reached the alarm engine (" + range + ", between " + io::format_utc_seconds(r.since_ns) + " and " +
             io::format_utc_seconds(obs.time_ns) +
             "): the twin lost this input (a restart beyond a backlog, or the network), the machine did not stop. "
             "Not a recording gap and not an operating change: the detectors go on from their state, and a level "
             "that moved meanwhile is judged as any other change.";
  events.push_back(e);
  // A point event, as the operating changes: raised and cleared at once (the service that lost the input keeps
  // its own input_lost alarm).
  e.state = AlarmState::Cleared;
  e.cleared_time_ns = obs.time_ns;
  events.push_back(std::move(e));
}

}  // namespace causal::alarms
