// The last message per id that alarm-recommender published on a keep-last topic, kept per asset group in
// DIR/<sanitised asset group><suffix> (--state-dir), so a restarted recommender publishes exactly what readers had
// before: recommendations (`.recommendations.state`) and the alarm messages with their decision (action, next
// level, hours to it: `.alarm_messages.state`; the engine checkpoint keeps the alarm events, not the advice
// attached when they were published). Written atomically (not fsync'ed) before each message is published.
#pragma once

#include "causal/dds/cdr_bytes.hpp"
#include "causal/io/file_names.hpp"
#include "causal/io/group_state_files.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

#include <spdlog/spdlog.h>

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
    for (const auto& file : io::files_with_suffix(dir_, Traits::kSuffix)) {
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
  // The file's field list (SaveFields / RestoreFields, causal/estimation/state_fields.hpp): its asset group and
  // the kept messages' CDR bytes.
  template <class Io, class G, class B>
  static void fields(Io io, G& group, B& bodies) {
    io.tag(Traits::kTag, Traits::kVersion);
    io(group, bodies);
  }
  void load(const std::string& file, std::vector<Msg>& out) {
    auto bytes = estimation::load_state_file(file);
    if (!bytes) return;
    estimation::StateReader in(std::move(*bytes));
    std::string group;
    std::vector<std::string> bodies;
    fields(estimation::RestoreFields{in}, group, bodies);
    if (path(group) != file) throw estimation::StateError("its content is for asset group '" + group + "'");
    auto& kept = kept_[group];
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      Msg m;
      if (!dds::from_cdr_bytes<PubSub>(bodies[i], m) || Traits::group(m) != group) {
        throw estimation::StateError("message " + std::to_string(i) + " is not readable");
      }
      kept[Traits::id(m)] = std::move(bodies[i]);
      out.push_back(std::move(m));
    }
    if (!in.at_end()) throw estimation::StateError("unexpected data after the messages");
  }
  void save(const std::string& group) {
    estimation::StateWriter out;
    std::vector<std::string> bodies;
    for (const auto& [id, bytes] : kept_[group]) bodies.push_back(bytes);
    fields(estimation::SaveFields{out}, group, bodies);
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
