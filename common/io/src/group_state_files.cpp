#include "causal/io/group_state_files.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/io/file_names.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace causal::io {

std::vector<std::string> files_with_suffix(const std::string& dir, const std::string& suffix) {
  std::vector<std::string> found;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.size() > suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      found.push_back(entry.path().string());
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

GroupStateFiles::GroupStateFiles(std::string dir, std::string suffix) : dir_(std::move(dir)), suffix_(std::move(suffix)) {
  if (dir_.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec || !std::filesystem::is_directory(dir_)) {
    throw std::invalid_argument("--state-dir '" + dir_ + "' cannot be created: " + ec.message());
  }
}

std::string GroupStateFiles::path(const std::string& asset_group) const {
  return (std::filesystem::path(dir_) / (safe_file_component(asset_group) + suffix_)).string();
}

std::optional<std::string> GroupStateFiles::load(const std::string& asset_group) const {
  if (!enabled()) return std::nullopt;
  return estimation::load_state_file(path(asset_group));
}

bool GroupStateFiles::save(const std::string& asset_group, const std::function<void(estimation::StateWriter&)>& fill) {
  if (!enabled()) return true;
  try {
    estimation::StateWriter w;
    fill(w);
    estimation::save_state_file(path(asset_group), w.bytes());
    ++saves_;
    return true;
  } catch (const estimation::StateError& e) {
    ++failures_;
    last_error_ = e.what();
    return false;
  }
}

}  // namespace causal::io
