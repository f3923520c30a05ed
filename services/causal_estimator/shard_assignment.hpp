// Which estimator shard owns which asset groups, from configuration (deploy/config/shards.yaml):
//   shards:
//     <shard name>: [<asset-group id or glob pattern>, ...]
// causal-estimator --shards FILE --shard NAME receives only the groups its patterns match (a content filter on
// its readers, see common/dds asset_group_filter.hpp). Patterns of different shards must not overlap: an
// identical pattern in two shards is refused here; overlapping globs cannot be judged without the groups, so
// each estimator logs the groups it took ("new asset group ...") and the summary counts them.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace causal::estimator {

struct ShardAssignment {
  std::map<std::string, std::vector<std::string>> shards;  // shard name -> ids / glob patterns

  // The patterns of `name`; throws std::invalid_argument naming the shards the file has.
  const std::vector<std::string>& patterns_of(const std::string& name) const;
};

// Throws causal::config::ConfigError naming the file and key (missing, empty list, pattern with spaces, a
// pattern in two shards).
ShardAssignment load_shard_assignment(const std::string& path);

}  // namespace causal::estimator
