#include "ingest_state_store.hpp"

#include "causal/io/file_names.hpp"
#include "causal/estimation/state_archive.hpp"

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace causal::ingest {

IngestStateStore::IngestStateStore(std::string dir) : dir_(std::move(dir)) {
  if (dir_.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec || !std::filesystem::is_directory(dir_)) {
    throw std::invalid_argument("--state-dir '" + dir_ + "' cannot be created: " + ec.message());
  }
}

std::string IngestStateStore::path(const std::string& asset_group) const {
  return (std::filesystem::path(dir_) / (io::safe_file_component(asset_group) + ".ingest.state")).string();
}

std::optional<ResumePoint> IngestStateStore::load(const std::string& asset_group) const {
  if (!enabled()) return std::nullopt;
  const std::string file = path(asset_group);
  try {
    const auto payload = load_state_file(file);
    if (!payload) return std::nullopt;
    StateReader r(*payload);
    r.expect("ingest_numbering", 1);
    const std::string saved_group = r.get<std::string>();
    if (saved_group != asset_group) throw StateError("it belongs to asset group '" + saved_group + "'");
    ResumePoint p;
    r.read(p.channels);
    r.read(p.next_sequence);
    r.read(p.next_sample_index);
    r.read(p.snapshot_index);
    return p;
  } catch (const StateError& e) {
    throw std::runtime_error("numbering state '" + file + "' cannot be used: " + e.what() +
                             " (move it away only if the estimator's checkpoint of this group goes too)");
  }
}

bool IngestStateStore::save(const std::string& asset_group, const ResumePoint& point) {
  if (!enabled()) return true;
  try {
    StateWriter w;
    w.begin("ingest_numbering", 1);
    w.put(asset_group);
    w.put(point.channels);
    w.put(point.next_sequence);
    w.put(point.next_sample_index);
    w.put(point.snapshot_index);
    save_state_file(path(asset_group), w.bytes());
    ++saves_;
    return true;
  } catch (const StateError& e) {
    ++failures_;
    last_error_ = e.what();
    return false;
  }
}

}  // namespace causal::ingest
