#include "causal/advice/alarm_state_store.hpp"

#include "causal/io/file_names.hpp"
#include "causal/io/group_state_files.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace causal::advice {

namespace {

constexpr const char* kTag = "alarm_recommender_stream";
constexpr std::uint32_t kVersion = 1;

const char* level_name(bool sample_level) { return sample_level ? "sample" : "condition"; }

// A checkpoint's field lists (SaveFields / RestoreFields, causal/estimation/state_fields.hpp): the stream it belongs
// to, then what the store keeps of it (the engine and the trends follow, each with its own save / restore).
template <class Io, class G, class B>
void stream_key_fields(Io io, G& asset_group, B& sample_level) {
  io.tag(kTag, kVersion);
  io(asset_group, sample_level);
}

template <class Io, class S>
void stream_fields(Io io, S& s) {
  bool has_index = s.last_index.has_value();
  std::uint64_t index = s.last_index.value_or(0);
  io(has_index, index);
  if constexpr (Io::restoring) {
    if (has_index) s.last_index = index;
  }
  auto events = static_cast<std::uint64_t>(s.last_events.size());
  io(events);
  if constexpr (Io::restoring) {
    for (; events > 0; --events) {
      alarms::AlarmEvent e;
      io.section(e);
      s.last_events[e.alarm_id] = e;
    }
  } else {
    for (const auto& [id, e] : s.last_events) io.section(e);
  }
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return "[" + s + "]";
}

}  // namespace

AlarmStateStore::AlarmStateStore(std::string state_dir, std::chrono::milliseconds sample_level_interval)
    : dir_(std::move(state_dir)), sample_interval_(sample_level_interval) {
  if (dir_.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec || !std::filesystem::is_directory(dir_)) {
    throw std::invalid_argument("--state-dir '" + dir_ + "' is not a usable directory" +
                                (ec ? ": " + ec.message() : std::string()));
  }
}

std::string AlarmStateStore::sanitise(const std::string& asset_group) { return io::safe_file_component(asset_group); }

std::string AlarmStateStore::path(const std::string& asset_group, bool sample_level) const {
  return (std::filesystem::path(dir_) / (sanitise(asset_group) + "." + level_name(sample_level) + ".alarms.state"))
      .string();
}

AlarmStateStore::Opened AlarmStateStore::open(const std::string& asset_group, bool sample_level,
                                              const std::vector<std::string>& channel_names,
                                              const std::vector<std::string>& factor_names,
                                              const alarms::AlarmParams& params,
                                              const prognosis::PrognosisParams& prognosis_params) {
  return open_stream(asset_group, sample_level, &channel_names, &factor_names, params, prognosis_params);
}

AlarmStateStore::Opened AlarmStateStore::open_checkpoint(const std::string& asset_group, bool sample_level,
                                                         const alarms::AlarmParams& params,
                                                         const prognosis::PrognosisParams& prognosis_params) {
  return open_stream(asset_group, sample_level, nullptr, nullptr, params, prognosis_params);
}

std::vector<AlarmStateStore::Found> AlarmStateStore::checkpoints() const {
  std::vector<Found> out;
  if (!enabled()) return out;
  // Sorted: the same restart publishes in the same order.
  for (const auto& file : io::files_with_suffix(dir_, ".alarms.state")) {
    try {
      auto bytes = estimation::load_state_file(file);
      if (!bytes) continue;  // removed meanwhile
      estimation::StateReader in(std::move(*bytes));
      Found f;
      stream_key_fields(estimation::RestoreFields{in}, f.asset_group, f.sample_level);
      if (path(f.asset_group, f.sample_level) != file) {
        throw estimation::StateError("its content is for asset group '" + f.asset_group + "' at " +
                                 level_name(f.sample_level) + " level, another file name");
      }
      out.push_back(std::move(f));
    } catch (const estimation::StateError& e) {
      throw estimation::StateError("checkpoint '" + file + "' cannot be used: " + e.what() +
                               ". Move it away to start this asset group over (the baseline is then re-learned "
                               "and alarm ids restart at 1)");
    }
  }
  return out;
}

AlarmStateStore::Opened AlarmStateStore::open_stream(const std::string& asset_group, bool sample_level,
                                                     const std::vector<std::string>* channel_names,
                                                     const std::vector<std::string>* factor_names,
                                                     const alarms::AlarmParams& params,
                                                     const prognosis::PrognosisParams& prognosis_params) {
  Opened out;
  Stream& s = streams_[{asset_group, sample_level}];
  s = Stream{};
  const std::string file = enabled() ? path(asset_group, sample_level) : std::string();
  try {
    std::optional<std::string> bytes;
    if (enabled()) bytes = estimation::load_state_file(file);  // nullopt: no checkpoint yet
    if (bytes) {
      estimation::StateReader in(std::move(*bytes));
      std::string group;
      bool sample = false;
      stream_key_fields(estimation::RestoreFields{in}, group, sample);
      if (group != asset_group || sample != sample_level) {
        throw estimation::StateError("it belongs to asset group '" + group + "' at " + level_name(sample) + " level");
      }
      stream_fields(estimation::RestoreFields{in}, s);
      out.engine = std::make_unique<alarms::AlarmEngine>(alarms::AlarmEngine::restore(in, params));
      if (!in.at_end()) {  // checkpoints written before the prognosis end here
        out.trends = std::make_unique<prognosis::ChannelTrends>(prognosis::ChannelTrends::restore(
            in, static_cast<int>(out.engine->channel_names().size()), prognosis_params));
      }
      if (!in.at_end()) throw estimation::StateError("unexpected data after the prognosis trends");
      if (channel_names != nullptr && out.engine->channel_names() != *channel_names) {
        throw estimation::StateError("it was written for channels " + joined(out.engine->channel_names()) +
                                 ", the stream has " + joined(*channel_names));
      }
      if (factor_names != nullptr && out.engine->factor_names() != *factor_names) {
        throw estimation::StateError("it was written for factors " + joined(out.engine->factor_names()) +
                                 ", the stream has " + joined(*factor_names) +
                                 " (did causal-estimator restart without its state and learn another causal order?)");
      }
      out.resumed = true;
      for (const auto& [id, e] : s.last_events) out.republish.push_back(e);
    }
  } catch (const estimation::StateError& e) {
    streams_.erase({asset_group, sample_level});
    throw estimation::StateError("checkpoint '" + file + "' cannot be used: " + e.what() +
                             ". Move it away to start this asset group over (the baseline is then re-learned "
                             "and alarm ids restart at 1)");
  }
  if (!out.engine) {
    if (channel_names == nullptr || factor_names == nullptr) {
      throw estimation::StateError("checkpoint '" + file + "' is gone: nothing to restore");
    }
    out.engine = std::make_unique<alarms::AlarmEngine>(asset_group, *channel_names, *factor_names, params);
  }
  if (!out.trends) {
    out.trends = std::make_unique<prognosis::ChannelTrends>(static_cast<int>(out.engine->channel_names().size()),
                                                            prognosis_params);
  }
  s.engine = out.engine.get();
  s.trends = out.trends.get();
  return out;
}

std::optional<std::uint64_t> AlarmStateStore::last_index(const std::string& asset_group, bool sample_level) const {
  const auto it = streams_.find({asset_group, sample_level});
  return it == streams_.end() ? std::nullopt : it->second.last_index;
}

bool AlarmStateStore::is_duplicate(const std::string& asset_group, bool sample_level, std::uint64_t index) {
  const auto it = streams_.find({asset_group, sample_level});
  if (it == streams_.end() || !it->second.last_index || index > *it->second.last_index) return false;
  ++duplicates_;
  return true;
}

void AlarmStateStore::record(const std::string& asset_group, bool sample_level, std::uint64_t index,
                             const std::vector<alarms::AlarmEvent>& events) {
  const Key key{asset_group, sample_level};
  const auto it = streams_.find(key);
  if (it == streams_.end()) throw std::logic_error("AlarmStateStore::record before open for '" + asset_group + "'");
  Stream& s = it->second;
  s.last_index = index;
  for (const auto& e : events) s.last_events[e.alarm_id] = e;
  s.unsaved = true;
  if (!enabled()) return;
  // Condition level: one observation per snapshot (minutes apart), so every one is written. Sample level:
  // throttled, but an observation with events is written at once, before they are published.
  const bool due = !sample_level || !events.empty() || !s.last_save || Clock::now() - *s.last_save >= sample_interval_;
  if (due) save(key, s);
}

void AlarmStateStore::flush() {
  if (!enabled()) return;
  for (auto& [key, s] : streams_)
    if (s.unsaved && s.engine != nullptr) save(key, s);
}

void AlarmStateStore::save(const Key& key, Stream& s) {
  estimation::StateWriter out;
  stream_key_fields(estimation::SaveFields{out}, key.first, key.second);
  stream_fields(estimation::SaveFields{out}, s);
  s.engine->save(out);
  if (s.trends != nullptr) s.trends->save(out);
  const std::string file = path(key.first, key.second);
  try {
    estimation::save_state_file(file, out.bytes());
    ++saves_;
    s.unsaved = false;
    s.last_save = Clock::now();
  } catch (const estimation::StateError& e) {
    // Reported on the first failure and then every 100th: a full disk must not flood the log.
    if (save_failures_++ % 100 == 0) {
      errors_.push_back("checkpoint not written (" + std::to_string(save_failures_) + " failures so far): " + e.what());
    }
  }
}

}  // namespace causal::advice
