#include "causal/config/config_search.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace causal::config {
namespace fs = std::filesystem;

namespace {

const char* env_name_of(ConfigKind kind) {
  return kind == ConfigKind::Dds ? "CAUSAL_TWIN_DDS_DIR" : "CAUSAL_TWIN_CONFIG_DIR";
}

const char* sub_dir_of(ConfigKind kind) { return kind == ConfigKind::Dds ? "dds" : "config"; }

}  // namespace

// No symlink resolution needed: /proc/self/exe is already canonical and CMake gives the build folder absolute.
bool is_inside_dir(const std::string& path, const std::string& dir) {
  const fs::path p = fs::path(path).lexically_normal();
  const fs::path d = fs::path(dir).lexically_normal();
  auto pi = p.begin();
  for (auto di = d.begin(); di != d.end(); ++di) {
    if (di->empty()) continue;  // trailing separator
    if (pi == p.end() || *pi != *di) return false;
    ++pi;
  }
  return true;
}

std::string ConfigChoice::describe(const std::string& file_name) const {
  if (found()) return path + " (" + (origin == "flag" ? std::string("from the command line") : "from " + origin) + ")";
  std::string places;
  for (const ConfigPlace& p : searched) places += (places.empty() ? "" : ", ") + p.dir;
  return file_name + " not found (looked in: " + places + ")";
}

SearchRoots process_roots(ConfigKind kind) {
  SearchRoots roots;
  roots.env_name = env_name_of(kind);
  if (const char* env = std::getenv(roots.env_name.c_str()); env != nullptr) roots.env_dir = env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    roots.installed_dir = (exe.parent_path().parent_path() / CAUSAL_TWIN_INSTALL_DATADIR / "causal-twin" /
                           sub_dir_of(kind)).string();
#ifdef CAUSAL_TWIN_BUILD_DIR
    if (is_inside_dir(exe.string(), CAUSAL_TWIN_BUILD_DIR)) {
      roots.build_tree_dir = (fs::path(CAUSAL_TWIN_SOURCE_DEPLOY_DIR) / sub_dir_of(kind)).string();
    }
#endif
  }
  return roots;
}

std::vector<ConfigPlace> config_places(const SearchRoots& roots) {
  std::vector<ConfigPlace> places;
  if (!roots.env_dir.empty()) places.push_back({roots.env_dir, "$" + roots.env_name});
  // Before /etc: a build-tree binary must not pick up an installed package's configuration.
  if (!roots.build_tree_dir.empty()) places.push_back({roots.build_tree_dir, "the source tree (build-tree binary)"});
  if (!roots.etc_dir.empty()) places.push_back({roots.etc_dir, roots.etc_dir});
  if (!roots.installed_dir.empty()) places.push_back({roots.installed_dir, "the installed defaults"});
  return places;
}

ConfigChoice find_config_file(const std::string& file_name, const std::string& flag_value, const SearchRoots& roots) {
  ConfigChoice choice;
  if (!flag_value.empty()) {
    choice.path = flag_value;
    choice.origin = "flag";
    return choice;
  }
  choice.searched = config_places(roots);
  for (const ConfigPlace& place : choice.searched) {
    const fs::path candidate = fs::path(place.dir) / file_name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) {
      choice.path = candidate.string();
      choice.origin = place.label;
      return choice;
    }
  }
  return choice;
}

ConfigChoice find_config_file(const std::string& file_name, const std::string& flag_value, ConfigKind kind) {
  return find_config_file(file_name, flag_value, process_roots(kind));
}

}  // namespace causal::config
