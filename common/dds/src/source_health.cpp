#include "causal/dds/source_health.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace causal::dds {

namespace {

double seconds(SourceHealth::Clock::duration d) { return std::chrono::duration<double>(d).count(); }

std::string fixed1(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

}  // namespace

SourceHealth::SourceHealth(double deadline_s) : deadline_s_(deadline_s) {
  if (!std::isfinite(deadline_s) || deadline_s < 0.0) {
    throw std::invalid_argument("health deadline must be finite and >= 0 s, got " + std::to_string(deadline_s));
  }
}

std::size_t SourceHealth::active_alarms() const {
  std::size_t n = 0;
  for (const auto& [name, s] : sources_) n += s.alarmed ? 1 : 0;
  return n;
}

HealthChange SourceHealth::change(HealthChange::Kind kind, const std::string& name, const Source& s,
                                  Clock::time_point now) {
  HealthChange c;
  c.kind = kind;
  c.source = name;
  c.has_index = s.has_index;
  c.last_index = s.last_index;
  c.silent_s = s.has_data ? seconds(now - s.last_data) : 0.0;
  return c;
}

void SourceHealth::raise(const std::string& name, Source& s, Clock::time_point now, const std::string& what,
                         std::vector<HealthChange>& out) {
  if (s.alarmed) return;  // one alarm per silence, whatever else is learned meanwhile
  s.alarmed = true;
  ++raised_;
  HealthChange c = change(HealthChange::Kind::Raised, name, s, now);
  c.reason = "input of '" + name + "' is silent: " + what + "; last data " +
             (s.has_data ? fixed1(c.silent_s) + " s ago" : std::string("never")) +
             (s.has_index ? " (snapshot " + std::to_string(s.last_index) + ")" : "");
  out.push_back(std::move(c));
}

void SourceHealth::clear(const std::string& name, Source& s, Clock::time_point now, const std::string& why,
                         std::vector<HealthChange>& out) {
  if (!s.alarmed) return;
  s.alarmed = false;
  ++cleared_;
  HealthChange c = change(HealthChange::Kind::Cleared, name, s, now);
  c.reason = "input of '" + name + "' " + why + " after " + fixed1(c.silent_s) + " s of silence";
  out.push_back(std::move(c));
}

void SourceHealth::on_data(const std::string& source, Clock::time_point now, std::vector<HealthChange>& out) {
  Source& s = sources_[source];
  clear(source, s, now, "has data again", out);  // measured before last_data moves, so it says how long it was silent
  s.state = State::Alive;
  s.last_data = now;
  s.has_data = true;
}

void SourceHealth::on_data(const std::string& source, std::uint64_t index, Clock::time_point now,
                           std::vector<HealthChange>& out) {
  on_data(source, now, out);
  Source& s = sources_[source];
  s.has_index = true;
  s.last_index = index;
}

void SourceHealth::on_ended(const std::string& source, Clock::time_point now, std::vector<HealthChange>& out) {
  Source& s = sources_[source];
  s.state = State::Ended;
  clear(source, s, now, "ended cleanly (its writer left)", out);
}

void SourceHealth::on_writer_lost(const std::string& source, Clock::time_point now, std::vector<HealthChange>& out) {
  Source& s = sources_[source];
  if (s.state == State::Ended) return;  // ended cleanly before its writer left: not a fault
  s.state = State::Lost;
  raise(source, s, now, "its writer was lost without ending the stream", out);
}

void SourceHealth::check(Clock::time_point now, std::vector<HealthChange>& out) {
  if (deadline_s_ <= 0.0) return;
  for (auto& [name, s] : sources_) {
    if (s.state != State::Alive || s.alarmed || !s.has_data) continue;
    if (seconds(now - s.last_data) >= deadline_s_) {
      raise(name, s, now, "no data within the deadline of " + fixed1(deadline_s_) + " s while its writer is alive", out);
    }
  }
}

}  // namespace causal::dds
