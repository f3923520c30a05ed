// Authorisation per asset group through DDS partitions, the one per-endpoint attribute
// Fast DDS 2.9's access control checks against the signed permissions (Permissions::check_create_datawriter
// locally, check_remote_datawriter for every remote writer: each partition a writer announces must be named by
// its grant; 2.9 parses no data tags). A sensor identity limited to some asset groups is granted the partitions
// "causal_twin/group/<group>" for its topics (deploy/security/issue-identity.sh --groups), its writers announce
// exactly those (GrantedPartitions below), and the estimator accepts from a writer only the groups its
// partitions name (partitions_allow_group). A writer without partitions (the empty partition) may write every
// group: on a secured bus only an identity whose grant names no partitions has one.
// Text only, no DDS: the participant hands in the verified grant and the partitions discovery reported.
#pragma once

#include <string>
#include <vector>

namespace causal::dds {

inline constexpr const char* kGroupPartitionPrefix = "causal_twin/group/";

inline std::string group_partition(const std::string& group) { return kGroupPartitionPrefix + group; }

// Whether a writer that announced `partitions` may write samples of `group`: yes when it announced none or the
// empty partition (its grant names no groups), else only when one partition is exactly group_partition(group)
// (literal: a partition with wildcards entitles to nothing, so a grant's pattern cannot widen a writer's reach).
bool partitions_allow_group(const std::vector<std::string>& partitions, const std::string& group);

// The allow rules of one permissions grant, as Fast DDS 2.9 applies them to an endpoint: the FIRST rule whose
// publish (subscribe) criteria name the topic (fnmatch) decides, with every partition of that rule's criteria of
// that kind; criteria without <partitions> stand for the empty partition.
class GrantedPartitions {
 public:
  GrantedPartitions() = default;
  // `grant_xml`: the text of one <grant> ... </grant> (its allow rules; deny rules end the search for a topic).
  static GrantedPartitions parse(const std::string& grant_xml);

  // The partitions an endpoint of `topic` announces so that its grant allows it: none (empty vector) when the
  // grant names only the empty partition or does not name the topic (Fast DDS then refuses the endpoint
  // itself); otherwise the granted names with the empty one first when granted.
  std::vector<std::string> for_endpoint(const std::string& topic, bool publish) const;

 private:
  struct Rule {
    bool allow = true;
    std::vector<std::string> publish_topics, publish_partitions, subscribe_topics, subscribe_partitions;
  };
  std::vector<Rule> rules_;
};

// Fast DDS's endpoint property "partitions": the names joined by ';' (the empty partition first, because a
// trailing empty name is dropped by the DataWriter's parser but kept by the security manager's).
std::string partitions_property(const std::vector<std::string>& partitions);

}  // namespace causal::dds
