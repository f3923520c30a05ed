// The partitions an endpoint announces from its grant, and the estimator's rule for a writer's partitions
// (common/dds/group_partitions.hpp), on grants written as deploy/security/issue-identity.sh writes them.
#include "causal/dds/group_partitions.hpp"

#include <gtest/gtest.h>

using causal::dds::GrantedPartitions;
using causal::dds::partitions_allow_group;
using causal::dds::partitions_property;

namespace {

const char* const kSensorGrant = R"(<grant name="s">
  <subject_name>CN=s</subject_name>
  <allow_rule><domains><id>1</id></domains>
    <publish><topics><topic>causal_twin/vibration_frame</topic><topic>causal_twin/condition_input</topic></topics>
      <partitions><partition>causal_twin/group/a</partition><partition>causal_twin/group/b</partition></partitions>
    </publish></allow_rule>
  <allow_rule><domains><id>1</id></domains>
    <subscribe><topics><topic>causal_twin/condition_vector</topic></topics></subscribe></allow_rule>
  <default>DENY</default></grant>)";

const char* const kEstimatorGrant = R"(<grant name="e">
  <allow_rule><publish><topics><topic>causal_twin/condition_vector</topic></topics></publish></allow_rule>
  <allow_rule><subscribe><topics><topic>causal_twin/*_input</topic><topic>causal_twin/condition_vector</topic></topics>
    <partitions><partition></partition><partition>causal_twin/group/*</partition></partitions></subscribe></allow_rule>
  </grant>)";

}  // namespace

TEST(GroupPartitions, WritersAnnounceTheirGrantedGroupsReadersTheEmptyPartitionFirst) {
  const auto sensor = GrantedPartitions::parse(kSensorGrant);
  const std::vector<std::string> ab = {"causal_twin/group/a", "causal_twin/group/b"};
  EXPECT_EQ(sensor.for_endpoint("causal_twin/condition_input", true), ab);
  EXPECT_EQ(sensor.for_endpoint("causal_twin/vibration_frame", true), ab);
  EXPECT_TRUE(sensor.for_endpoint("causal_twin/condition_vector", false).empty());  // only the empty partition
  EXPECT_TRUE(sensor.for_endpoint("causal_twin/alarm", true).empty());              // not granted at all
  const auto estimator = GrantedPartitions::parse(kEstimatorGrant);
  const std::vector<std::string> any = {"", "causal_twin/group/*"};
  EXPECT_EQ(estimator.for_endpoint("causal_twin/condition_input", false), any);  // topic pattern
  EXPECT_EQ(estimator.for_endpoint("causal_twin/condition_vector", false), any);
  EXPECT_TRUE(estimator.for_endpoint("causal_twin/condition_vector", true).empty());
  EXPECT_EQ(partitions_property(any), ";causal_twin/group/*");
  EXPECT_TRUE(GrantedPartitions::parse("").for_endpoint("causal_twin/condition_input", true).empty());
}

TEST(GroupPartitions, AWriterMayWriteOnlyTheGroupsItsPartitionsNameLiterally) {
  EXPECT_TRUE(partitions_allow_group({}, "anything"));
  EXPECT_TRUE(partitions_allow_group({"", "causal_twin/group/a"}, "b"));  // the empty partition: every group
  EXPECT_TRUE(partitions_allow_group({"causal_twin/group/a", "causal_twin/group/b"}, "b"));
  EXPECT_FALSE(partitions_allow_group({"causal_twin/group/a"}, "b"));
  EXPECT_FALSE(partitions_allow_group({"causal_twin/group/*"}, "b"));  // a pattern entitles to nothing
  EXPECT_FALSE(partitions_allow_group({"causal_twin/group/a"}, "a2"));
  EXPECT_FALSE(partitions_allow_group({"group/a"}, "a"));
}
