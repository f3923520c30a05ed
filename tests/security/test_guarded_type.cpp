// GuardedPubSubType without DDS: every malformed payload of the fuzz corpus is refused (deserialize returns
// false, nothing thrown), every decodable one within the limits is accepted, the key hash equals the generated
// code's for keys it can handle (the instance handles on the wire do not change) and a 300-byte key no longer
// throws. Counting: the refusal is counted once per sample, in the getKey that follows the failed decode.
#include "causal/dds/guarded_type.hpp"
#include "fuzz_corpus.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <memory>

using namespace causal::test::fuzz;
using causal::dds::GuardedPubSubType;

namespace {

// Decodes `bytes` with the guarded type of `type_name` into a fresh sample, then computes its key as Fast
// DDS's receive path does. Returns whether the decode was accepted.
template <typename PubSubType>
bool guarded_decode(const Bytes& bytes) {
  GuardedPubSubType<PubSubType> t;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = static_cast<std::uint32_t>(bytes.size());
  void* data = t.createData();
  const bool ok = t.deserialize(&payload, data);
  eprosima::fastrtps::rtps::InstanceHandle_t handle;
  EXPECT_TRUE(t.getKey(data, &handle, false));
  EXPECT_TRUE(handle.isDefined());
  EXPECT_EQ(handle == causal::dds::refused_sample_handle(), !ok);
  t.deleteData(data);
  return ok;
}

std::function<bool(const Bytes&)> decoder_for(const std::string& type_name) {
  using namespace causal_twin;
  if (type_name == "causal_twin::VibrationFrame") return guarded_decode<VibrationFramePubSubType>;
  if (type_name == "causal_twin::ConditionVector") return guarded_decode<ConditionVectorPubSubType>;
  if (type_name == "causal_twin::CausalFactorBatch") return guarded_decode<CausalFactorBatchPubSubType>;
  if (type_name == "causal_twin::Alarm") return guarded_decode<AlarmPubSubType>;
  if (type_name == "causal_twin::Recommendation") return guarded_decode<RecommendationPubSubType>;
  if (type_name == "causal_twin::WhatIfRequest") return guarded_decode<WhatIfRequestPubSubType>;
  if (type_name == "causal_twin::WhatIfReply") return guarded_decode<WhatIfReplyPubSubType>;
  return nullptr;
}

}  // namespace

TEST(GuardedType, RefusesEveryMalformedSampleAndAcceptsTheRestCountingEachRefusalOnce) {
  std::size_t refused = 0, accepted = 0;
  for (const auto& corpus : every_topic()) {
    const auto decode = decoder_for(corpus.type_name);
    ASSERT_TRUE(decode) << corpus.type_name;
    for (std::size_t i = 0; i < corpus.refused.size(); ++i) {
      const auto before = causal::dds::refusals_total();
      EXPECT_FALSE(decode(corpus.refused[i])) << corpus.topic << " refused[" << i << "]";
      EXPECT_EQ(causal::dds::refusals_total(), before + 1) << corpus.topic << " refused[" << i << "]";
      ++refused;
    }
    for (std::size_t i = 0; i < corpus.accepted.size(); ++i) {
      const auto before = causal::dds::refusals_total();
      EXPECT_TRUE(decode(corpus.accepted[i])) << corpus.topic << " accepted[" << i << "]";
      EXPECT_EQ(causal::dds::refusals_total(), before) << corpus.topic << " accepted[" << i << "]";
      ++accepted;
    }
  }
  std::printf("guarded type: %zu malformed samples refused (one count each), %zu accepted\n", refused, accepted);
  EXPECT_GE(refused, 40u);
}

TEST(GuardedType, KeyHashEqualsTheGeneratedOneAndALongKeyNoLongerThrows) {
  using causal_twin::CausalFactorBatchPubSubType;
  GuardedPubSubType<CausalFactorBatchPubSubType> guarded;
  for (const std::string& group : std::vector<std::string>{"ims2-shaft1", "", "ab", std::string(255, 'g')}) {
    auto b = factor_batch(group);
    b.kind(causal_twin::FIXED_LAG_SMOOTHER);
    eprosima::fastrtps::rtps::InstanceHandle_t expected, got;
    // A fresh generated type each time: it reuses one key buffer and leaves the padding after a string
    // unwritten, so after another key its hash of "" or "ab" (padding before the enums) differs.
    CausalFactorBatchPubSubType plain;
    ASSERT_TRUE(plain.getKey(&b, &expected, false));
    ASSERT_TRUE(guarded.getKey(&b, &got, false));
    EXPECT_EQ(got, expected) << "group of " << group.size() << " bytes";
  }
  // The generated code's history dependence, shown (the guard's hash has none):
  {
    CausalFactorBatchPubSubType plain;
    auto first = factor_batch("ims2-shaft1"), second = factor_batch("ab");
    eprosima::fastrtps::rtps::InstanceHandle_t fresh, after_other, guarded_twice;
    CausalFactorBatchPubSubType().getKey(&second, &fresh, false);
    plain.getKey(&first, &after_other, false);
    plain.getKey(&second, &after_other, false);
    EXPECT_NE(after_other, fresh) << "the generated getKey no longer depends on earlier keys";
    guarded.getKey(&first, &guarded_twice, false);
    guarded.getKey(&second, &guarded_twice, false);
    EXPECT_EQ(guarded_twice, fresh);
  }
  CausalFactorBatchPubSubType plain;
  auto b = factor_batch(std::string(256, 'g'));
  eprosima::fastrtps::rtps::InstanceHandle_t h1, h2;
  EXPECT_THROW(plain.getKey(&b, &h1, false), eprosima::fastcdr::exception::NotEnoughMemoryException)
      << "the generated code no longer throws: this guard may be obsolete";
  EXPECT_TRUE(guarded.getKey(&b, &h1, false));
  b.asset_group(std::string(100000, 'g'));
  EXPECT_TRUE(guarded.getKey(&b, &h2, false));
  EXPECT_NE(h1, h2);
}

TEST(GuardedType, ChannelNamesMeetTheOneNameLimit) {
  // 255-byte channel names (causal/io/name_limits.hpp) are taken, 256-byte ones refused and counted once, in
  // frames and condition vectors alike (64 kB names used to be processed, then refused by every reader of the
  // factors as outcome_name id_too_long).
  using namespace causal_twin;
  for (const std::size_t bytes : {std::size_t{255}, std::size_t{256}}) {
    const bool allowed = bytes <= causal::io::kMaxNameBytes;
    auto f = frame("fuzz-g");
    f.channel_names({"b1", "b2", std::string(bytes, 'c'), "b4"});
    auto v = condition("fuzz-g");
    v.channel_names({"b1", "b2", "b3", std::string(bytes, 'c')});
    const auto before = causal::dds::refusals_total();
    EXPECT_EQ(guarded_decode<VibrationFramePubSubType>(encode<VibrationFramePubSubType>(f)), allowed) << bytes;
    EXPECT_EQ(guarded_decode<ConditionVectorPubSubType>(encode<ConditionVectorPubSubType>(v)), allowed) << bytes;
    EXPECT_EQ(causal::dds::refusals_total(), before + (allowed ? 0u : 2u)) << bytes;
  }
}

// An alarm action and alarm-recommender's result repeat the same fields and share one check: each id at most
// kMaxIdBytes, the action kind one of the three. A valid one is taken; each id one byte too long, or an action
// kind out of range, is refused and counted once, in both types alike.
template <typename PubSubType, typename Sample>
void expect_alarm_action_limits(Sample valid) {
  const std::string too_long(causal::dds::kMaxIdBytes + 1, 'x');
  std::vector<Sample> refused;
  for (int field = 0; field < 5; ++field) {
    Sample s = valid;
    if (field == 0) s.request_id(too_long);
    if (field == 1) s.asset_group(too_long);
    if (field == 2) s.alarm_id(too_long);
    if (field == 3) s.user_name(too_long);
    if (field == 4) s.reason(too_long);
    refused.push_back(s);
  }
  Sample bad_kind = valid;
  bad_kind.action(static_cast<causal_twin::AlarmActionKind>(3));
  refused.push_back(bad_kind);
  const auto before = causal::dds::refusals_total();
  EXPECT_TRUE(guarded_decode<PubSubType>(encode<PubSubType>(valid)));
  for (std::size_t i = 0; i < refused.size(); ++i) {
    EXPECT_FALSE(guarded_decode<PubSubType>(encode<PubSubType>(refused[i]))) << "refused[" << i << "]";
  }
  EXPECT_EQ(causal::dds::refusals_total(), before + refused.size());
}

TEST(GuardedType, AlarmActionsAndTheirResultsMeetTheSameLimits) {
  using namespace causal_twin;
  AlarmAction a;
  a.request_id("r1");
  a.asset_group("g");
  a.alarm_id("g/1/feature_drift/0");
  a.user_name("ann");
  a.reason("sensor under repair");
  a.action(SHELVE);
  expect_alarm_action_limits<AlarmActionPubSubType>(a);
  AlarmActionResult r;
  r.request_id("r1");
  r.asset_group("g");
  r.alarm_id("g/1/feature_drift/0");
  r.user_name("ann");
  r.reason("sensor under repair");
  r.action(SHELVE);
  expect_alarm_action_limits<AlarmActionResultPubSubType>(r);
}
