// AlarmManager's checkpoint: one tagged, versioned section ("alarm_management", version 1) from one field list
// (SaveFields / RestoreFields, causal/estimation/state_fields.hpp), so what restore reads is what save wrote. A
// field added later goes at the end of the list with a new version.
#include "causal/alarm_management/alarm_management.hpp"
#include "causal/estimation/state_fields.hpp"

namespace causal::alarm_management {

namespace {

constexpr const char* kTag = "alarm_management";
constexpr std::uint32_t kVersion = 1;

// A map or a deque as its size and its entries; `entry(io, element)` is the element's own field list.
template <class Map, class Entry>
void entries(estimation::SaveFields io, const Map& m, Entry entry) {
  io.out.put(static_cast<std::uint64_t>(m.size()));
  for (const auto& e : m) entry(io, e);
}

template <class K, class V, class Entry>
void entries(estimation::RestoreFields io, std::map<K, V>& m, Entry entry) {
  m.clear();
  for (auto n = io.in.get<std::uint64_t>(); n > 0; --n) {
    std::pair<K, V> e;
    entry(io, e);
    m.insert(std::move(e));
  }
}

template <class Entry>
void entries(estimation::RestoreFields io, std::deque<std::string>& d, Entry entry) {
  d.clear();
  for (auto n = io.in.get<std::uint64_t>(); n > 0; --n) entry(io, d.emplace_back());
}

template <class Io, class O>
void outcome_fields(Io io, O& o) {
  io(o.applied, o.refusal, o.error, o.acknowledged, o.shelved);
}

}  // namespace

template <class Io, class M>
void AlarmManager::fields(Io io, M& m) {
  entries(io, m.alarms_, [](auto f, auto& e) {
    f(e.first, e.second.asset_group, e.second.open, e.second.acknowledged, e.second.raised_time_ns);
  });
  entries(io, m.cleared_order_, [](auto f, auto& id) { f(id); });
  entries(io, m.shelved_, [](auto f, auto& e) {
    f(e.first, e.second.asset_group, e.second.alarm_id, e.second.until_ns);
  });
  entries(io, m.raises_by_source_, [](auto f, auto& e) {
    f(e.first.first, e.first.second, e.second);
  });
  entries(io, m.raises_by_group_, [](auto f, auto& e) {
    f(e.first, e.second);
  });
  entries(io, m.outcomes_, [](auto f, auto& e) {
    f(e.first);
    outcome_fields(f, e.second);
  });
  entries(io, m.outcome_order_, [](auto f, auto& id) { f(id); });
}

void AlarmManager::save(estimation::StateWriter& out) const {
  out.begin(kTag, kVersion);
  fields(estimation::SaveFields{out}, *this);
}

void AlarmManager::restore(estimation::StateReader& in) {
  in.expect(kTag, kVersion);
  AlarmManager m(limits_);
  fields(estimation::RestoreFields{in}, m);
  for (const auto& [id, o] : m.outcomes_) {
    if (o.refusal < Refusal::None || o.refusal > Refusal::NotApplicable) {
      throw estimation::StateError("checkpoint: alarm_management outcome '" + id + "' has an unknown refusal");
    }
  }
  if (m.outcomes_.size() != m.outcome_order_.size()) {
    throw estimation::StateError("checkpoint: alarm_management request outcomes and their order differ");
  }
  m.counters_ = counters_;  // this process's counts (not saved)
  *this = std::move(m);
}

}  // namespace causal::alarm_management
