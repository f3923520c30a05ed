// Malformed samples of every topic type, as the bytes a hostile writer puts on the wire (CDR payload with
// its 4-byte encapsulation header). Two kinds per topic:
//  * `refused`: the guard (common/dds guarded_type.hpp) must refuse them before any service sees them: a key
//    longer than 255 bytes (it used to end the estimator and the recommender), a string length of 4 GiB, a
//    truncated sample, a bool byte other than 0/1, a bad encapsulation, an enum out of range, a sequence over
//    its IDL bound, an over-long non-key id;
//  * `accepted`: decodable samples within the limits whose content is wrong (NaN and infinities, wrong channel
//    counts, channel 0 or 999, an empty group): these reach the services, which must count and survive them.
#pragma once

#include "bus_samples.hpp"
#include "causal/dds/topics.hpp"
#include "causal_twinPubSubTypes.h"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace causal::test::fuzz {

using Bytes = std::vector<unsigned char>;

struct TopicCorpus {
  std::string topic;
  std::string type_name;
  std::string writer_profile;
  std::vector<Bytes> refused;
  std::vector<Bytes> accepted;
};

template <typename PubSubType>
Bytes encode(typename PubSubType::type sample) {
  PubSubType t;
  const std::uint32_t size = t.getSerializedSizeProvider(&sample)();
  eprosima::fastrtps::rtps::SerializedPayload_t payload(size);
  if (!t.serialize(&sample, &payload)) return {};
  return Bytes(payload.data, payload.data + payload.length);
}

inline const double kNaN = std::numeric_limits<double>::quiet_NaN();
inline const double kInf = std::numeric_limits<double>::infinity();
inline const std::string kLongId(300, 'k');

// The malformations that need no knowledge of the type: a 4 GiB length in the first field (every type starts
// with a string key), the first half of a valid sample, an unknown encapsulation.
inline void add_generic(TopicCorpus& c, const Bytes& valid) {
  c.refused.push_back(Bytes{0x00, 0x01, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 'h', 'u', 'g', 'e'});
  c.refused.push_back(Bytes(valid.begin(), valid.begin() + static_cast<long>(valid.size() / 2)));
  Bytes bad_encapsulation = valid;
  bad_encapsulation[0] = 0x7F;
  bad_encapsulation[1] = 0x13;
  c.refused.push_back(bad_encapsulation);
}

// `sample` changed by `change`, encoded and added to `into` (a corpus's refused or accepted samples).
template <typename PubSubType, typename Change>
void add_changed(std::vector<Bytes>& into, typename PubSubType::type sample, Change change) {
  change(sample);
  into.push_back(encode<PubSubType>(sample));
}

// Sets the last byte (a trailing boolean) to 7: Fast CDR throws BadParamException.
inline Bytes with_bad_trailing_bool(Bytes b) {
  b.back() = 7;
  return b;
}

inline causal_twin::VibrationFrame frame(const std::string& group) {
  causal_twin::VibrationFrame f = security::four_bearing_frame(group, 4);
  f.source("fuzz");
  return f;
}

inline TopicCorpus vibration_frames() {
  using T = causal_twin::VibrationFramePubSubType;
  TopicCorpus c{dds::topics::kVibrationFrame, "causal_twin::VibrationFrame", dds::profiles::kVibrationFrameWriter, {}, {}};
  add_generic(c, encode<T>(frame("fuzz-g")));
  c.refused.push_back(encode<T>(frame(kLongId)));
  add_changed<T>(c.refused, frame("fuzz-g"), [](auto& f) { f.channel_names(std::vector<std::string>(65, "c")); });
  // Accepted by the guard, wrong in content (a long source is free text, not an id):
  add_changed<T>(c.accepted, frame("fuzz-long-source"), [](auto& f) { f.source(std::string(5000, 's')); });
  add_changed<T>(c.accepted, frame("fuzz-nan"),
                 [](auto& f) { f.samples({kNaN, kInf, -kInf, 1.0, kNaN, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}); });
  add_changed<T>(c.accepted, frame("fuzz-count"), [](auto& f) { f.samples(std::vector<double>(10, 0.5)); });  // 4 x 4 expected
  add_changed<T>(c.accepted, frame("fuzz-huge-n"), [](auto& f) { f.samples_per_channel(4000000000u); });
  add_changed<T>(c.accepted, frame("fuzz-rate"), [](auto& f) {
    f.sample_rate_hz(kNaN);
    f.channel_names({});
  });
  c.accepted.push_back(encode<T>(frame("")));
  return c;
}

inline causal_twin::ConditionVector condition(const std::string& group) {
  causal_twin::ConditionVector v;
  v.asset_group(group);
  v.feature("meanabs");
  v.snapshot_index(0);
  v.channel_names({"b1", "b2", "b3", "b4"});
  v.values({0.1, 0.1, 0.1, 0.1});
  return v;
}

inline TopicCorpus condition_vectors(const std::string& topic, const std::string& profile) {
  using T = causal_twin::ConditionVectorPubSubType;
  TopicCorpus c{topic, "causal_twin::ConditionVector", profile, {}, {}};
  const Bytes valid = encode<T>(condition("fuzz-g"));
  add_generic(c, valid);
  c.refused.push_back(with_bad_trailing_bool(valid));
  c.refused.push_back(encode<T>(condition(kLongId)));
  add_changed<T>(c.refused, condition("fuzz-g"), [](auto& v) { v.feature(kLongId); });
  add_changed<T>(c.refused, condition("fuzz-g"), [](auto& v) { v.values(std::vector<double>(65, 0.1)); });
  add_changed<T>(c.accepted, condition("fuzz-nan"), [](auto& v) { v.values({kNaN, kInf, 0.1, -kInf}); });
  add_changed<T>(c.accepted, condition("fuzz-count"), [](auto& v) { v.values({0.1, 0.2}); });
  add_changed<T>(c.accepted, condition("fuzz-index"), [](auto& v) {
    v.snapshot_index(std::numeric_limits<std::uint64_t>::max());
    v.feature("no-such-feature");
  });
  c.accepted.push_back(encode<T>(condition("")));
  return c;
}

inline causal_twin::CausalFactorBatch factor_batch(const std::string& group) {
  causal_twin::CausalFactorBatch b;
  b.asset_group(group);
  b.kind(causal_twin::FILTER);
  b.time_scale(causal_twin::CONDITION_LEVEL);
  b.feature("meanabs");
  b.channel_count(4);
  b.lag_order(1);
  b.order_confidence(kNaN);
  b.order_source("learned");
  for (unsigned short k = 1; k <= 4; ++k) {
    causal_twin::OutcomeFactors o;
    o.outcome(k);
    o.outcome_name("b" + std::to_string(k));
    o.factor_names({"x12", "xL11"});
    o.factors({0.5, 0.1});
    o.factor_std({0.1, 0.1});
    b.outcomes().push_back(o);
  }
  return b;
}

inline TopicCorpus factor_batches() {
  using T = causal_twin::CausalFactorBatchPubSubType;
  TopicCorpus c{dds::topics::kCausalFactors, "causal_twin::CausalFactorBatch", dds::profiles::kCausalFactorsWriter, {}, {}};
  add_generic(c, encode<T>(factor_batch("fuzz-g")));
  c.refused.push_back(encode<T>(factor_batch(kLongId)));
  add_changed<T>(c.refused, factor_batch("fuzz-g"), [](auto& b) { b.kind(static_cast<causal_twin::EstimateKind>(7)); });
  add_changed<T>(c.refused, factor_batch("fuzz-g"),
                 [](auto& b) { b.outcomes()[0].factors(std::vector<double>(1025, 0.0)); });
  add_changed<T>(c.accepted, factor_batch("fuzz-nan"), [](auto& b) {
    b.outcomes()[1].factors({kNaN, kInf});
    b.outcomes()[2].factor_std({-1.0, kNaN});
  });
  add_changed<T>(c.accepted, factor_batch("fuzz-count"), [](auto& b) {
    b.channel_count(9);  // four outcomes follow
    b.outcomes()[3].outcome(99);
    b.outcomes()[0].factor_names({"x12"});  // two factors
  });
  add_changed<T>(c.accepted, factor_batch("fuzz-empty"), [](auto& b) {
    b.outcomes().clear();
    b.channel_count(0);
  });
  add_changed<T>(c.accepted, factor_batch("fuzz-cov"),
                 [](auto& b) { b.outcomes()[0].factor_covariance({1.0, kNaN}); });  // 3 expected for 2 factors
  return c;
}

inline causal_twin::Alarm alarm(const std::string& id) {
  causal_twin::Alarm a;
  a.alarm_id(id);
  a.asset_group("fuzz-g");
  a.channel(1);
  a.severity(causal_twin::CRITICAL);
  a.state(causal_twin::RAISED);
  a.kind("fuzz");
  a.category("degradation");
  return a;
}

inline TopicCorpus alarms() {
  using T = causal_twin::AlarmPubSubType;
  TopicCorpus c{dds::topics::kAlarm, "causal_twin::Alarm", dds::profiles::kAlarmWriter, {}, {}};
  add_generic(c, encode<T>(alarm("fuzz/1/fuzz/0")));
  c.refused.push_back(encode<T>(alarm(kLongId)));
  add_changed<T>(c.refused, alarm("fuzz/1/fuzz/1"), [](auto& a) { a.asset_group(kLongId); });
  add_changed<T>(c.refused, alarm("fuzz/1/fuzz/2"), [](auto& a) { a.severity(static_cast<causal_twin::Severity>(9)); });
  add_changed<T>(c.refused, alarm("fuzz/1/fuzz/3"), [](auto& a) { a.factor_now(std::vector<double>(100, 1.0)); });
  add_changed<T>(c.accepted, alarm("fuzz/999/fuzz/4"), [](auto& a) {
    a.channel(999);
    a.root_cause_channel(500);
    a.score(kNaN);
    a.root_cause_confidence(kInf);
    a.factor_names({"x12", "x13"});
    a.factor_now({kNaN});
  });
  add_changed<T>(c.accepted, alarm(""), [](auto& a) {
    a.asset_group("");
    a.channel(0);
  });
  return c;
}

inline causal_twin::Recommendation recommendation(const std::string& id) {
  causal_twin::Recommendation r;
  r.recommendation_id(id);
  r.alarm_id("fuzz/1/fuzz/0");
  r.asset_group("fuzz-g");
  r.rank(1);
  r.target_channel(1);
  r.intervene_channel(2);
  r.answer_kind("horizon");
  return r;
}

inline TopicCorpus recommendations() {
  using T = causal_twin::RecommendationPubSubType;
  TopicCorpus c{dds::topics::kRecommendation, "causal_twin::Recommendation", dds::profiles::kRecommendationWriter, {}, {}};
  add_generic(c, encode<T>(recommendation("fuzz/0/1")));
  c.refused.push_back(encode<T>(recommendation(kLongId)));
  add_changed<T>(c.refused, recommendation("fuzz/0/2"), [](auto& r) { r.asset_group(kLongId); });
  add_changed<T>(c.accepted, recommendation("fuzz/0/3"), [](auto& r) {
    r.target_channel(999);
    r.intervene_channel(0);
    r.delta(kNaN);
    r.effect_low(kInf);
    r.effect_high(-kInf);
  });
  return c;
}

inline causal_twin::WhatIfRequest whatif_request(const std::string& id) {
  causal_twin::WhatIfRequest q;
  q.request_id(id);
  q.asset_group("fuzz-g");
  q.intervene_channel(1);
  q.delta(0.1);
  q.sustained(true);
  return q;
}

inline TopicCorpus whatif_requests() {
  using T = causal_twin::WhatIfRequestPubSubType;
  TopicCorpus c{dds::topics::kWhatIfRequest, "causal_twin::WhatIfRequest", dds::profiles::kWhatIfWriter, {}, {}};
  const Bytes valid = encode<T>(whatif_request("fuzz-q0"));
  add_generic(c, valid);
  c.refused.push_back(with_bad_trailing_bool(valid));
  c.refused.push_back(encode<T>(whatif_request(kLongId)));
  add_changed<T>(c.refused, whatif_request("fuzz-q1"), [](auto& q) { q.asset_group(kLongId); });
  add_changed<T>(c.accepted, whatif_request("fuzz-q2"), [](auto& q) { q.intervene_channel(0); });
  add_changed<T>(c.accepted, whatif_request("fuzz-q3"), [](auto& q) {
    q.intervene_channel(999);
    q.delta(kNaN);
  });
  add_changed<T>(c.accepted, whatif_request("fuzz-q4"), [](auto& q) {
    q.delta(kInf);
    q.asset_group("");
  });
  return c;
}

inline TopicCorpus whatif_replies() {
  using T = causal_twin::WhatIfReplyPubSubType;
  TopicCorpus c{dds::topics::kWhatIfReply, "causal_twin::WhatIfReply", dds::profiles::kWhatIfWriter, {}, {}};
  causal_twin::WhatIfReply r;
  r.request_id("fuzz-r0");
  r.asset_group("fuzz-g");
  r.ok(true);
  r.channel_names({"b1", "b2"});
  r.effect_immediate({0.1, 0.2});
  add_generic(c, encode<T>(r));
  add_changed<T>(c.refused, r, [](auto& bad) { bad.request_id(kLongId); });
  add_changed<T>(c.refused, r, [](auto& bad) { bad.effect_median(std::vector<double>(70, 0.0)); });
  add_changed<T>(c.accepted, r, [](auto& bad) {
    bad.request_id("fuzz-r1");
    bad.effect_immediate({kNaN, kInf, 1.0});  // three values, two names
  });
  return c;
}

// Every topic a service reads, each with its corpus.
inline std::vector<TopicCorpus> every_topic() {
  return {vibration_frames(),
          condition_vectors(dds::topics::kConditionInput, dds::profiles::kConditionInputWriter),
          condition_vectors(dds::topics::kConditionVector, dds::profiles::kConditionVectorWriter),
          factor_batches(),
          alarms(),
          recommendations(),
          whatif_requests(),
          whatif_replies()};
}

}  // namespace causal::test::fuzz
