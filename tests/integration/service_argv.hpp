// The command-line pieces the process tests share: the IMS test-2 feature table shipped in deploy/data, and a
// service bounded by --idle-exit and --max-runtime.
#pragma once

#include <string>
#include <vector>

namespace causal::test {

// The IMS test-2 feature table shipped in deploy/data (984 snapshots of four bearings).
inline std::string ims2_feature_table() {
  return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
}

// `bin` on `domain`, leaving `idle_exit` seconds after its input stops and at the latest after `max_runtime`
// seconds; `extra` (e.g. {"--wait-for", "alarm-recommender"}) after these.
inline std::vector<std::string> service_argv(const std::string& bin, const std::string& domain,
                                             const std::string& idle_exit, const std::string& max_runtime,
                                             const std::vector<std::string>& extra = {}) {
  std::vector<std::string> argv{bin, "--domain", domain, "--idle-exit", idle_exit, "--max-runtime", max_runtime};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}

// "--wait-for <name>" for each name: the service starts once every one of them is discovered.
inline std::vector<std::string> wait_for(const std::vector<std::string>& names) {
  std::vector<std::string> argv;
  for (const std::string& name : names) argv.insert(argv.end(), {"--wait-for", name});
  return argv;
}

}  // namespace causal::test
