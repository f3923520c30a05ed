#include "ingest_state_store.hpp"

#include "causal/estimation/state_archive.hpp"

#include <stdexcept>

namespace causal::ingest {

std::optional<ResumePoint> IngestStateStore::load(const std::string& asset_group) const {
  const std::string file = path(asset_group);
  try {
    const auto payload = files_.load(asset_group);
    if (!payload) return std::nullopt;
    estimation::StateReader r(*payload);
    // Version 1 (before the source's sequence was kept) still resumes: the blocks lost across that one restart are
    // then not known.
    const auto tag = r.get<std::string>();
    const auto version = r.get<std::uint32_t>();
    if (tag != "ingest_numbering" || (version != 1 && version != 2))
      throw estimation::StateError("section '" + tag + "' version " + std::to_string(version) + " is not ingest_numbering 1 or 2");
    const std::string saved_group = r.get<std::string>();
    if (saved_group != asset_group) throw estimation::StateError("it belongs to asset group '" + saved_group + "'");
    ResumePoint p;
    r.read(p.channels);
    r.read(p.next_sequence);
    r.read(p.next_sample_index);
    r.read(p.snapshot_index);
    if (version >= 2) {
      r.read(p.has_source_sequence);
      r.read(p.last_source_sequence);
    }
    return p;
  } catch (const estimation::StateError& e) {
    throw std::runtime_error("numbering state '" + file + "' cannot be used: " + e.what() +
                             " (move it away only if the estimator's checkpoint of this group goes too)");
  }
}

bool IngestStateStore::save(const std::string& asset_group, const ResumePoint& point) {
  return files_.save(asset_group, [&](estimation::StateWriter& w) {
    w.begin("ingest_numbering", 2);
    w.put(asset_group);
    w.put(point.channels);
    w.put(point.next_sequence);
    w.put(point.next_sample_index);
    w.put(point.snapshot_index);
    w.put(point.has_source_sequence);
    w.put(point.last_source_sequence);
  });
}

}  // namespace causal::ingest
