// Ready-made feature rows (sensor-ingest's condition_input path): the same bounds as the raw blocks' parsers:
// nothing deeper than a row's two levels is parsed, duplicate keys are refused in both encodings, and a 16 MiB
// message costs at most a small multiple of its bytes.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <string>

#include "feature_row.hpp"

namespace causal::ingest {
namespace {

const std::string kJson =
    R"({"asset_group":"pump-1","feature":"meanabs","channels":["b1","b2"],"time_ns":1700000000000000000,)"
    R"("sequence":17,"values":[0.12,null],"discontinuity":true})";
const std::string kCsv =
    "#features asset_group=pump-1 feature=meanabs channels=b1,b2 time_ns=1700000000000000000 sequence=17 values=0.12,nan";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

TEST(FeatureRow, JsonAndCsvDecodeTheSameRow) {
  for (const auto& message : {kJson, kCsv}) {
    ASSERT_TRUE(is_feature_row(message)) << message;
    const auto r = parse_feature_row(message);
    ASSERT_TRUE(r.row) << r.detail;
    EXPECT_EQ(r.row->asset_group, "pump-1");
    EXPECT_EQ(r.row->feature, "meanabs");
    EXPECT_EQ(r.row->channels, (std::vector<std::string>{"b1", "b2"}));
    ASSERT_EQ(r.row->values.size(), 2u);
    EXPECT_DOUBLE_EQ(r.row->values[0], 0.12);
    EXPECT_EQ(r.row->non_finite, 1u);
    EXPECT_EQ(r.row->time_ns, 1700000000000000000);
    EXPECT_EQ(r.row->sequence, 17u);
  }
  EXPECT_TRUE(parse_feature_row(kJson).row->discontinuity);
}

TEST(FeatureRow, DuplicateKeysAreRefusedInBothEncodings) {
  const auto json = parse_feature_row(replaced(kJson, R"("sequence":17)", R"("sequence":17,"sequence":18)"));
  EXPECT_FALSE(json.row);
  EXPECT_EQ(json.reason, RejectReason::Malformed);
  EXPECT_EQ(json.detail, "duplicate key 'sequence'");
  const auto csv = parse_feature_row(replaced(kCsv, "sequence=17", "sequence=17 sequence=18"));
  EXPECT_FALSE(csv.row);
  EXPECT_EQ(csv.detail, "duplicate key 'sequence'");
}

TEST(FeatureRow, WrongTypesAndNestingAreRefused) {
  EXPECT_EQ(parse_feature_row(replaced(kJson, R"("asset_group":"pump-1")", R"("asset_group":5)")).reason,
            RejectReason::Field);
  EXPECT_EQ(parse_feature_row(replaced(kJson, "0.12,null", R"("x",null)")).reason, RejectReason::Field);
  EXPECT_EQ(parse_feature_row(replaced(kJson, "0.12,null", "[0.12],null")).reason, RejectReason::Malformed);
  EXPECT_EQ(parse_feature_row(replaced(kJson, R"("sequence":17)", R"("sequence":1.5)")).reason, RejectReason::Field);
  EXPECT_EQ(parse_feature_row(replaced(kJson, R"("sequence":17,)", "")).reason, RejectReason::Field);
  EXPECT_EQ(parse_feature_row(replaced(kJson, "0.12,null", "0.12")).reason, RejectReason::Shape);
  EXPECT_EQ(parse_feature_row(R"({"values":[1]} {"values":[2]})").reason, RejectReason::Malformed);
}

TEST(FeatureRow, MemoryIsBoundedByTheMessage) {
  // 16 MiB messages shaped to cost the most: nested arrays, a flat array of values, a channel list of commas.
  const std::size_t bytes = (16u << 20) - 256;
  std::string message;
  message.reserve(bytes + 256);
  message.append(R"({"asset_group":"g","values":)").append(bytes, '[');
  const auto nested = parse_feature_row(message);
  EXPECT_EQ(nested.reason, RejectReason::Malformed);
  message.assign(R"({"asset_group":"g","feature":"f","time_ns":0,"sequence":0,"values":[0)");
  while (message.size() < bytes) message.append(",0");
  message.append("]}");
  const auto values = parse_feature_row(message);
  EXPECT_EQ(values.reason, RejectReason::Shape);
  EXPECT_EQ(values.detail, "more than 64 values");
  message.assign("#features asset_group=g feature=f time_ns=0 sequence=0 values=0 channels=").append(bytes, ',');
  const auto channels = parse_feature_row(message);
  EXPECT_EQ(channels.reason, RejectReason::Shape);
  EXPECT_LT(peak_rss_mib(), 100.0);
}

}  // namespace
}  // namespace causal::ingest
