#include "shard_assignment.hpp"

#include "causal/config/yaml_fields.hpp"

#include <stdexcept>

namespace causal::estimator {

const std::vector<std::string>& ShardAssignment::patterns_of(const std::string& name) const {
  const auto it = shards.find(name);
  if (it != shards.end()) return it->second;
  std::string known;
  for (const auto& [n, p] : shards) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("no shard '" + name + "' in the shard assignment (it has: " + known + ")");
}

ShardAssignment load_shard_assignment(const std::string& path) {
  const config::Section root = config::Section::load_file(path);
  root.only({"shards"});
  const YAML::Node node = root.node()["shards"];
  if (!node.IsMap() || node.size() == 0) root.fail("shards", "must map shard names to lists of asset groups");
  ShardAssignment a;
  std::map<std::string, std::string> owner;  // pattern -> shard
  for (const auto& entry : node) {
    const std::string name = entry.first.as<std::string>();
    const std::string key = "shards." + name;
    if (!entry.second.IsSequence() || entry.second.size() == 0) {
      root.fail(key, "must be a non-empty list of asset-group ids or glob patterns");
    }
    auto& patterns = a.shards[name];
    for (const auto& item : entry.second) {
      if (!item.IsScalar()) root.fail(key, "every entry must be an asset-group id or glob pattern");
      const std::string p = item.as<std::string>();
      if (p.empty() || p.find_first_of(" \t\r\n") != std::string::npos) {
        root.fail(key, "'" + p + "': an asset-group id or pattern has no spaces and is not empty");
      }
      if (const auto it = owner.find(p); it != owner.end()) {
        root.fail(key, "'" + p + "' is also in shard '" + it->second + "': a group would be processed twice");
      }
      owner.emplace(p, name);
      patterns.push_back(p);
    }
  }
  return a;
}

}  // namespace causal::estimator
