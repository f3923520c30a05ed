// A participant the secured pipeline must ignore: it tries to read every topic and keeps publishing fake
// frames, condition inputs, condition vectors and a critical alarm (asset group / alarm id "intruder...").
// What its own permissions refuse locally is noted (not an error: a rogue would try it anyway); what it
// receives is counted per topic, split into its own samples (a control that it works) and everyone else's.
#pragma once

#include "bus_samples.hpp"
#include "loopback_settings.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/security.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace causal::test::security {

inline constexpr const char* kIntruderGroup = "intruder";

struct IntruderCounts {
  std::map<std::string, std::size_t> foreign;  // per topic: samples from anyone else (must stay 0)
  std::map<std::string, std::size_t> own;      // per topic: its own samples, read back
  std::map<std::string, std::size_t> matched;  // per topic: most remote endpoints ever matched
  std::map<std::string, std::size_t> sent;     // per topic: samples written
  std::set<std::string> refused_locally;       // "read <topic>" / "write <topic>" its permissions forbid
  std::set<std::string> local_pairs;           // topics it both reads and writes (they match each other)
};

class Intruder {
 public:
  // `security_dir` "" = no credentials at all; else a PKI folder and identity (e.g. another CA's).
  Intruder(int domain_id, const std::string& security_dir, const std::string& identity) : participant_(settings(
      domain_id, security_dir, identity)) {
    namespace t = dds::topics;
    namespace p = dds::profiles;
    using namespace causal_twin;
    reader<VibrationFramePubSubType>(t::kVibrationFrame, p::kVibrationFrameReader,
                                     [](const auto& s) { return s.asset_group() == kIntruderGroup; });
    reader<ConditionVectorPubSubType>(t::kConditionInput, p::kConditionInputReader,
                                      [](const auto& s) { return s.asset_group() == kIntruderGroup; });
    reader<ConditionVectorPubSubType>(t::kConditionVector, p::kConditionVectorReader,
                                      [](const auto& s) { return s.asset_group() == kIntruderGroup; });
    reader<CausalFactorBatchPubSubType>(t::kCausalFactors, p::kCausalFactorsReader, [](const auto&) { return false; });
    reader<AlarmPubSubType>(t::kAlarm, p::kAlarmReader,
                            [](const auto& s) { return s.asset_group() == kIntruderGroup; });
    reader<RecommendationPubSubType>(t::kRecommendation, p::kRecommendationReader, [](const auto&) { return false; });
    reader<WhatIfRequestPubSubType>(t::kWhatIfRequest, p::kWhatIfReader, [](const auto&) { return false; });
    reader<WhatIfReplyPubSubType>(t::kWhatIfReply, p::kWhatIfReader, [](const auto&) { return false; });

    writer<VibrationFramePubSubType>(t::kVibrationFrame, p::kVibrationFrameWriter, four_bearing_frame(kIntruderGroup, 16));
    ConditionVector vector;
    vector.asset_group(kIntruderGroup);
    vector.feature("meanabs");
    vector.channel_names({"b1", "b2", "b3", "b4"});
    vector.values({0.1, 0.1, 0.1, 0.1});
    writer<ConditionVectorPubSubType>(t::kConditionInput, p::kConditionInputWriter, vector);
    writer<ConditionVectorPubSubType>(t::kConditionVector, p::kConditionVectorWriter, vector);
    Alarm alarm;
    alarm.alarm_id(std::string(kIntruderGroup) + "/1/fake/0");
    alarm.asset_group(kIntruderGroup);
    alarm.channel(1);
    alarm.severity(CRITICAL);
    alarm.state(RAISED);
    alarm.kind("fake");
    alarm.category("degradation");
    writer<AlarmPubSubType>(t::kAlarm, p::kAlarmWriter, alarm);
    for (const char* topic : {t::kVibrationFrame, t::kConditionInput, t::kConditionVector, t::kAlarm}) {
      if (!counts_.refused_locally.count(std::string("read ") + topic) &&
          !counts_.refused_locally.count(std::string("write ") + topic)) {
        counts_.local_pairs.insert(topic);
      }
    }
    thread_ = std::thread([this] { run(); });
  }
  ~Intruder() {
    stop_ = true;
    thread_.join();
  }

  IntruderCounts counts() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return counts_;
  }

 private:
  struct Endpoint {
    virtual ~Endpoint() = default;
    virtual void poll(IntruderCounts& c) = 0;  // read what arrived or write one sample
  };

  static dds::DdsSettings settings(int domain_id, const std::string& dir, const std::string& identity) {
    dds::DdsSettings s = causal::test::loopback_settings(domain_id, "intruder");
    s.security_dir = dir.empty() ? dds::kSecurityOff : dir;
    s.security_identity = identity;
    return s;
  }

  template <typename PubSub, typename IsOwn>
  void reader(const std::string& topic, const std::string& profile, IsOwn is_own) {
    struct R : Endpoint {
      R(dds::Participant& p, const std::string& t, const std::string& pr, IsOwn is_own)
          : r(p, t, pr), topic(t), own(is_own) {}
      void poll(IntruderCounts& c) override {
        r.take_all([&](const auto& s, const auto&) { ++(own(s) ? c.own[topic] : c.foreign[topic]); });
        c.matched[topic] = std::max(c.matched[topic], r.matched_writers());
      }
      dds::TypedReader<PubSub> r;
      std::string topic;
      IsOwn own;
    };
    try {
      endpoints_.push_back(std::make_unique<R>(participant_, topic, profile, is_own));
    } catch (const std::exception&) {  // refused: by its permissions when secured
      counts_.refused_locally.insert("read " + topic);
    }
  }

  template <typename PubSub>
  void writer(const std::string& topic, const std::string& profile, typename PubSub::type sample) {
    struct W : Endpoint {
      W(dds::Participant& p, const std::string& t, const std::string& pr, typename PubSub::type s)
          : w(p, t, pr), topic(t), sample(std::move(s)) {}
      void poll(IntruderCounts& c) override {
        const std::atomic<bool> never{false};
        if (w.write(sample, never, std::chrono::milliseconds(200)) == dds::WriteResult::Ok) ++c.sent[topic];
        c.matched[topic + " (writer)"] = std::max(c.matched[topic + " (writer)"], w.matched_readers());
      }
      dds::TypedWriter<PubSub> w;
      std::string topic;
      typename PubSub::type sample;
    };
    try {
      endpoints_.push_back(std::make_unique<W>(participant_, topic, profile, std::move(sample)));
    } catch (const std::exception&) {  // refused: by its permissions when secured
      counts_.refused_locally.insert("write " + topic);
    }
  }

  void run() {
    while (!stop_) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& e : endpoints_) e->poll(counts_);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }

  dds::Participant participant_;
  std::vector<std::unique_ptr<Endpoint>> endpoints_;
  mutable std::mutex mutex_;
  IntruderCounts counts_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace causal::test::security
