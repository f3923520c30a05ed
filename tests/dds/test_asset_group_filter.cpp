// The asset-group selection and content filter of estimator shards (causal/dds/asset_group_filter.hpp):
// glob matching, the filter expression (parse <-> text), and reading the asset group from payloads serialized
// by the generated type support (the same bytes a writer hands to the filter), in both byte orders.
#include "causal/dds/asset_group_filter.hpp"

#include "causal_twinPubSubTypes.h"

#include <gtest/gtest.h>

#include <fastdds/rtps/common/SerializedPayload.h>

#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace {

using causal::dds::AssetGroupSelection;
using causal::dds::glob_match;
using causal::dds::leading_cdr_string;

template <typename PubSubType>
std::vector<unsigned char> serialize(typename PubSubType::type& msg) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&msg)());
  EXPECT_TRUE(type.serialize(&msg, &payload));
  return std::vector<unsigned char>(payload.data, payload.data + payload.length);
}

}  // namespace

TEST(AssetGroupFilter, GlobMatchesStarsQuestionMarksAndLiterals) {
  // pattern, name, whether the pattern matches the name.
  const std::vector<std::tuple<std::string, std::string, bool>> cases = {
      {"sim-000*", "sim-0007", true},
      {"sim-000*", "sim-000", true},
      {"sim-000*", "sim-0017", false},
      {"sim-001?", "sim-0019", true},
      {"sim-001?", "sim-001", false},
      {"sim-001?", "sim-00190", false},
      {"*shaft*", "ims2-shaft1", true},
      {"*", "", true},
      {"a*b*c", "aXXbYYbZc", true},
      {"a*b*c", "aXXbYYbZ", false},
      {"ims2-shaft1", "ims2-shaft1", true},
      {"ims2-shaft1", "ims2-shaft10", false}};
  for (const auto& [pattern, name, matches] : cases) EXPECT_EQ(glob_match(pattern, name), matches) << pattern << " ~ " << name;
}

TEST(AssetGroupFilter, ExpressionsRoundTripAndSelect) {
  const auto hash = AssetGroupSelection::parse("hash 2/5");
  EXPECT_EQ(hash.hash_index, 2);
  EXPECT_EQ(hash.hash_count, 5);
  EXPECT_EQ(hash.expression(), "hash 2/5");
  EXPECT_FALSE(hash.all());
  const auto groups = AssetGroupSelection::parse("groups sim-00* ims2-shaft1");
  EXPECT_EQ(groups.patterns, (std::vector<std::string>{"sim-00*", "ims2-shaft1"}));
  EXPECT_EQ(AssetGroupSelection::parse(groups.expression()).patterns, groups.patterns);
  EXPECT_TRUE(groups.matches("sim-0042"));
  EXPECT_TRUE(groups.matches("ims2-shaft1"));
  EXPECT_FALSE(groups.matches("sim-0142"));
  EXPECT_TRUE(AssetGroupSelection::parse("").all());
  EXPECT_EQ(AssetGroupSelection{}.expression(), "");
  // FNV-1a 64 of "a" is 0xaf63dc4c8601ec8c (published test vector): 0xaf63dc4c8601ec8c % 7 == 1.
  EXPECT_EQ(causal::dds::asset_group_hash("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_TRUE(AssetGroupSelection::hash_slice(0xaf63dc4c8601ec8cULL % 7, 7).matches("a"));
  EXPECT_FALSE(AssetGroupSelection::hash_slice((0xaf63dc4c8601ec8cULL + 1) % 7, 7).matches("a"));
}

TEST(AssetGroupFilter, MalformedExpressionsAreRefused) {
  for (const char* bad : {"hash 3/3", "hash -1/2", "hash 1", "hash 1/2 extra", "hash a/b", "groups", "ids x"}) {
    EXPECT_THROW(AssetGroupSelection::parse(bad), std::invalid_argument) << bad;
  }
}

TEST(AssetGroupFilter, ReadsTheAssetGroupOfSerializedFramesAndConditionVectors) {
  causal_twin::VibrationFrame frame;
  frame.asset_group("ims2-shaft1");
  frame.samples(std::vector<double>(4096, 1.5));
  const auto bytes = serialize<causal_twin::VibrationFramePubSubType>(frame);
  const auto group = leading_cdr_string(bytes.data(), bytes.size());
  ASSERT_TRUE(group.has_value());
  EXPECT_EQ(*group, "ims2-shaft1");

  causal_twin::ConditionVector cv;
  cv.asset_group("pump-7");
  cv.feature("rms");
  const auto cv_bytes = serialize<causal_twin::ConditionVectorPubSubType>(cv);
  ASSERT_TRUE(leading_cdr_string(cv_bytes.data(), cv_bytes.size()).has_value());
  EXPECT_EQ(*leading_cdr_string(cv_bytes.data(), cv_bytes.size()), "pump-7");
}

TEST(AssetGroupFilter, BigEndianPayloadsAndDamagedOnesAreHandled) {
  // CDR_BE encapsulation, length 4 (with the NUL) big-endian, "abc".
  const std::vector<unsigned char> be = {0, 0, 0, 0, 0, 0, 0, 4, 'a', 'b', 'c', 0};
  ASSERT_TRUE(leading_cdr_string(be.data(), be.size()).has_value());
  EXPECT_EQ(*leading_cdr_string(be.data(), be.size()), "abc");
  // Truncated (length past the end), no NUL, zero length, another encoding (PL_CDR_LE 0x0003): not read.
  const std::vector<unsigned char> cut = {0, 1, 0, 0, 9, 0, 0, 0, 'a', 'b', 'c', 0};
  const std::vector<unsigned char> no_nul = {0, 1, 0, 0, 4, 0, 0, 0, 'a', 'b', 'c', 'd'};
  const std::vector<unsigned char> empty = {0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  const std::vector<unsigned char> pl = {0, 3, 0, 0, 4, 0, 0, 0, 'a', 'b', 'c', 0};
  for (const auto* p : {&cut, &no_nul, &empty, &pl}) EXPECT_FALSE(leading_cdr_string(p->data(), p->size()).has_value());
  EXPECT_FALSE(leading_cdr_string(be.data(), 7).has_value());
  EXPECT_FALSE(leading_cdr_string(nullptr, 0).has_value());
}
