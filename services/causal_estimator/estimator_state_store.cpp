#include "estimator_state_store.hpp"

#include "causal/estimation/state_archive.hpp"


namespace causal::estimator {

bool EstimatorStateStore::restore(const std::string& asset_group, pipeline::AssetPipeline& pipeline,
                                  std::vector<std::string>& resend, std::int64_t* last_time_ns) const {
  const std::string file = path(asset_group);
  const auto payload = files_.load(asset_group);
  if (!payload) return false;
  try {
    estimation::StateReader r(*payload);
    // Version 3 adds the data time of the last input fed; version 2 checkpoints are still read (time unknown).
    const std::string tag = r.get<std::string>();
    const auto version = r.get<std::uint32_t>();
    if (tag != "estimator_asset" || (version != 2 && version != 3)) {
      throw estimation::StateError("expected section 'estimator_asset' version 2 or 3, found '" + tag + "' version " +
                       std::to_string(version));
    }
    const std::string saved_group = r.get<std::string>();
    if (saved_group != asset_group) {
      throw estimation::StateError("it belongs to asset group '" + saved_group + "'");
    }
    pipeline.restore(r);
    r.read(resend);
    std::int64_t time_ns = INT64_MIN;
    if (version >= 3) r.read(time_ns);
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
    w.begin("estimator_asset", 3);
    w.put(asset_group);
    pipeline.save(w);
    w.put(resend);
    w.put(last_time_ns);
  });
}

}  // namespace causal::estimator
