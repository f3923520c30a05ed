#include "ingest_state_store.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

#include <stdexcept>

namespace causal::ingest {

namespace {

constexpr const char* kTag = "ingest_numbering";
constexpr std::uint32_t kVersion = 2;

// The numbering's field list (SaveFields / RestoreFields, causal/estimation/state_fields.hpp) as written at
// `version`: version 1 ends before the source's sequence.
template <class Io, class P>
void numbering_fields(Io io, P& p, std::uint32_t version) {
  io(p.channels, p.next_sequence, p.next_sample_index, p.snapshot_index);
  if (version >= 2) io(p.has_source_sequence, p.last_source_sequence);
}

}  // namespace

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
    if (tag != kTag || (version != 1 && version != kVersion))
      throw estimation::StateError("section '" + tag + "' version " + std::to_string(version) + " is not ingest_numbering 1 or 2");
    const std::string saved_group = r.get<std::string>();
    if (saved_group != asset_group) throw estimation::StateError("it belongs to asset group '" + saved_group + "'");
    ResumePoint p;
    numbering_fields(estimation::RestoreFields{r}, p, version);
    return p;
  } catch (const estimation::StateError& e) {
    throw std::runtime_error("numbering state '" + file + "' cannot be used: " + e.what() +
                             " (move it away only if the estimator's checkpoint of this group goes too)");
  }
}

bool IngestStateStore::save(const std::string& asset_group, const ResumePoint& point) {
  return files_.save(asset_group, [&](estimation::StateWriter& w) {
    w.begin(kTag, kVersion);
    w.put(asset_group);
    numbering_fields(estimation::SaveFields{w}, point, kVersion);
  });
}

}  // namespace causal::ingest
