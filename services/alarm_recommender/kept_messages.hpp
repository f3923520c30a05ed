// The last message per id that alarm-recommender published on a keep-last topic, kept per asset group in
// DIR/<sanitised asset group><suffix> (--state-dir), so a restarted recommender publishes exactly what readers had
// before: recommendations (`.recommendations.state`) and the alarm messages with their decision (action, next
// level, hours to it: `.alarm_messages.state`; the engine checkpoint keeps the alarm events, not the advice
// attached when they were published). Written atomically (not fsync'ed) before each message is published.
#pragma once

#include "causal/dds/cdr_bytes.hpp"
#include "causal/io/file_names.hpp"
#include "causal/estimation/state_archive.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace causal::recommender {

// `Traits` names the file (kTag, kVersion, kSuffix, kWhat), gives a message's id and asset group, and whether a
// message is worth keeping (keep).
template <typename Msg, typename PubSub, typename Traits>
class KeptMessages {
 public:
  explicit KeptMessages(std::string state_dir) : dir_(std::move(state_dir)) {}

  // Remembers `m` (replacing the last one with its id) and writes its asset group's file. A failed write is
  // counted and logged, never thrown: the messages keep flowing when the disk is full.
  // A message Traits::keep() refuses (a cleared alarm: nothing left to republish with it) removes its id.
  void record(const Msg& m) {
    if (dir_.empty()) return;
    auto& kept = kept_[Traits::group(m)];
    if (Traits::keep(m)) {
      kept[Traits::id(m)] = dds::to_cdr_bytes<PubSub>(m);
    } else if (kept.erase(Traits::id(m)) == 0) {
      return;  // nothing kept changed
    }
    save(Traits::group(m));
  }
  // The kept message of `id` in `group` (false when none).
  bool find(const std::string& group, const std::string& id, Msg& out) const {
    const auto g = kept_.find(group);
    if (g == kept_.end()) return false;
    const auto it = g->second.find(id);
    return it != g->second.end() && dds::from_cdr_bytes<PubSub>(it->second, out);
  }
  // Every message of every file in the directory (also kept for find()). Throws estimation::StateError naming the
  // file when one cannot be used.
  std::vector<Msg> load_all() {
    std::vector<Msg> out;
    if (dir_.empty()) return out;
    for (const auto& file : files()) {
      try {
        load(file, out);
      } catch (const estimation::StateError& e) {
        throw estimation::StateError(std::string(Traits::kWhat) + " checkpoint '" + file + "' cannot be used: " + e.what() +
                                 ". Move it away (its messages are then not published again)");
      }
    }
    return out;
  }
  std::uint64_t save_failures() const { return save_failures_; }

 private:
  std::string path(const std::string& group) const {
    return (std::filesystem::path(dir_) / (io::safe_file_component(group) + Traits::kSuffix)).string();
  }
  std::vector<std::string> files() const {
    const std::string suffix = Traits::kSuffix;
    std::vector<std::string> found;
    for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      if (entry.is_regular_file() && name.size() > suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        found.push_back(entry.path().string());
      }
    }
    std::sort(found.begin(), found.end());
    return found;
  }
  void load(const std::string& file, std::vector<Msg>& out) {
    auto bytes = estimation::load_state_file(file);
    if (!bytes) return;
    estimation::StateReader in(std::move(*bytes));
    in.expect(Traits::kTag, Traits::kVersion);
    const auto group = in.get<std::string>();
    if (path(group) != file) throw estimation::StateError("its content is for asset group '" + group + "'");
    const auto n = in.get<std::uint64_t>();
    auto& kept = kept_[group];
    for (std::uint64_t i = 0; i < n; ++i) {
      const auto body = in.get<std::string>();
      Msg m;
      if (!dds::from_cdr_bytes<PubSub>(body, m) || Traits::group(m) != group) {
        throw estimation::StateError("message " + std::to_string(i) + " is not readable");
      }
      kept[Traits::id(m)] = body;
      out.push_back(std::move(m));
    }
    if (!in.at_end()) throw estimation::StateError("unexpected data after the messages");
  }
  void save(const std::string& group) {
    estimation::StateWriter out;
    out.begin(Traits::kTag, Traits::kVersion);
    out.put(group);
    const auto& kept = kept_[group];
    out.put(static_cast<std::uint64_t>(kept.size()));
    for (const auto& [id, bytes] : kept) out.put(bytes);
    try {
      estimation::save_state_file(path(group), out.bytes());
    } catch (const estimation::StateError& e) {
      if (save_failures_++ % 100 == 0) {
        spdlog::error("{} checkpoint not written ({} failures so far): {}", Traits::kWhat, save_failures_, e.what());
      }
    }
  }

  std::string dir_;
  std::map<std::string, std::map<std::string, std::string>> kept_;  // group -> id -> message (CDR bytes)
  std::uint64_t save_failures_ = 0;
};

}  // namespace causal::recommender
