#include "estimator_state_store.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

namespace causal::estimator {

namespace {

constexpr const char* kSection = "estimator_asset";
// Version 3 added the data time of the last input fed; version 2 checkpoints are still read (time unknown).
constexpr std::uint32_t kVersion = 3;

// The checkpoint's one field list (SaveFields / RestoreFields, state_fields.hpp), so what restore reads is what
// save wrote. The asset group comes first and is checked before anything is restored: a file renamed to another
// group's name is refused, not taken for that group's state. Group and Resend are const when saving.
template <class IO, class Group, class Pipeline, class Resend, class Time>
void checkpoint_fields(IO io, std::uint32_t version, Group& asset_group, Pipeline& pipeline, Resend& resend,
                       Time& last_time_ns) {
  io.same(asset_group, "asset group", "file's asset group");
  io.object(pipeline);
  io(resend);
  if (version >= 3) io(last_time_ns);
}

}  // namespace

bool EstimatorStateStore::restore(const std::string& asset_group, pipeline::AssetPipeline& pipeline,
                                  std::vector<std::string>& resend, std::int64_t* last_time_ns) const {
  const std::string file = path(asset_group);
  const auto payload = files_.load(asset_group);
  if (!payload) return false;
  try {
    estimation::StateReader r(*payload);
    const std::string tag = r.get<std::string>();
    const auto version = r.get<std::uint32_t>();
    if (tag != kSection || (version != 2 && version != kVersion)) {
      throw estimation::StateError("expected section 'estimator_asset' version 2 or 3, found '" + tag + "' version " +
                                   std::to_string(version));
    }
    std::int64_t time_ns = INT64_MIN;
    checkpoint_fields(estimation::RestoreFields{r}, version, asset_group, pipeline, resend, time_ns);
    if (last_time_ns != nullptr) *last_time_ns = time_ns;
  } catch (const estimation::StateError& e) {
    throw estimation::StateError("checkpoint '" + file + "' cannot be used: " + e.what() +
                                 " (move it away to start this asset group over)");
  }
  return true;
}

bool EstimatorStateStore::save(const std::string& asset_group, const pipeline::AssetPipeline& pipeline,
                               const std::vector<std::string>& resend, std::int64_t last_time_ns) {
  return files_.save(asset_group, [&](estimation::StateWriter& w) {
    w.begin(kSection, kVersion);
    checkpoint_fields(estimation::SaveFields{w}, kVersion, asset_group, pipeline, resend, last_time_ns);
  });
}

}  // namespace causal::estimator
