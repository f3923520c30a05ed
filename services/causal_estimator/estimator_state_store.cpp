#include "estimator_state_store.hpp"

#include "causal/io/file_names.hpp"
#include "causal/state_archive.hpp"

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace causal::estimator {

EstimatorStateStore::EstimatorStateStore(std::string dir) : dir_(std::move(dir)) {
  if (dir_.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec || !std::filesystem::is_directory(dir_)) {
    throw std::invalid_argument("--state-dir '" + dir_ + "' cannot be created: " + ec.message());
  }
}

std::string EstimatorStateStore::path(const std::string& asset_group) const {
  return (std::filesystem::path(dir_) / (io::safe_file_component(asset_group) + ".estimator.state")).string();
}

bool EstimatorStateStore::restore(const std::string& asset_group, pipeline::AssetPipeline& pipeline,
                                  std::vector<std::string>& resend) const {
  if (!enabled()) return false;
  const std::string file = path(asset_group);
  const auto payload = load_state_file(file);
  if (!payload) return false;
  try {
    StateReader r(*payload);
    r.expect("estimator_asset", 2);
    const std::string saved_group = r.get<std::string>();
    if (saved_group != asset_group) {
      throw StateError("it belongs to asset group '" + saved_group + "'");
    }
    pipeline.restore(r);
    r.read(resend);
  } catch (const StateError& e) {
    throw StateError("checkpoint '" + file + "' cannot be used: " + e.what() +
                     " (move it away to start this asset group over)");
  }
  return true;
}

bool EstimatorStateStore::save(const std::string& asset_group, const pipeline::AssetPipeline& pipeline,
                               const std::vector<std::string>& resend) {
  if (!enabled()) return true;
  try {
    StateWriter w;
    w.begin("estimator_asset", 2);
    w.put(asset_group);
    pipeline.save(w);
    w.put(resend);
    save_state_file(path(asset_group), w.bytes());
    ++saves_;
    return true;
  } catch (const StateError& e) {
    ++failures_;
    last_error_ = e.what();
    return false;
  }
}

}  // namespace causal::estimator
