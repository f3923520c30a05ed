#include "causal/dds/sample_limits.hpp"

#include "causal/io/enum_names.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <utility>

namespace causal::dds {

const char* refusal_name(Refusal r) {
  static constexpr auto kNames = io::enum_names<Refusal>({{Refusal::None, "none"},
                                                          {Refusal::Malformed, "malformed"},
                                                          {Refusal::KeyTooLong, "key_too_long"},
                                                          {Refusal::IdTooLong, "id_too_long"},
                                                          {Refusal::BadEnum, "bad_enum"},
                                                          {Refusal::SequenceTooLong, "sequence_too_long"}});
  return kNames.name(r, "unknown");
}

namespace {

// Accumulates the first failed check; every check_limits is a list of these.
class Checker {
 public:
  explicit Checker(std::string& why) : why_(why) {}
  Checker& id(const char* field, const std::string& value) {
    if (result_ == Refusal::None && value.size() > kMaxIdBytes) {
      fail(Refusal::IdTooLong, std::string(field) + " of " + std::to_string(value.size()) + " bytes (at most " +
                                   std::to_string(kMaxIdBytes) + ")");
    }
    return *this;
  }
  // A list of names (channels): its length within its bound, then every name within the name limit.
  template <typename Names>
  Checker& names(const char* field, const Names& values, std::size_t bound) {
    sequence(field, values.size(), bound);
    for (const auto& v : values) id(field, v);
    return *this;
  }
  Checker& sequence(const char* field, std::size_t size, std::size_t bound) {
    if (result_ == Refusal::None && size > bound) {
      fail(Refusal::SequenceTooLong,
           std::string(field) + " with " + std::to_string(size) + " entries (at most " + std::to_string(bound) + ")");
    }
    return *this;
  }
  Checker& enumeration(const char* field, std::uint32_t value, std::uint32_t count) {
    if (result_ == Refusal::None && value >= count) {
      fail(Refusal::BadEnum, std::string(field) + " = " + std::to_string(value) + " (defined: 0.." +
                                 std::to_string(count - 1) + ")");
    }
    return *this;
  }
  Refusal result() const { return result_; }

 private:
  void fail(Refusal r, std::string why) {
    result_ = r;
    why_ = std::move(why);
  }
  std::string& why_;
  Refusal result_ = Refusal::None;
};

// An alarm action and its result carry the same fields (the result repeats the request).
template <typename ActionOrResult>
Refusal check_alarm_action(const ActionOrResult& s, std::string& why) {
  return Checker(why)
      .id("request_id", s.request_id())
      .id("asset_group", s.asset_group())
      .id("alarm_id", s.alarm_id())
      .id("user_name", s.user_name())
      .id("reason", s.reason())
      .enumeration("action", static_cast<std::uint32_t>(s.action()), 3)
      .result();
}

}  // namespace

Refusal check_limits(const causal_twin::VibrationFrame& s, std::string& why) {
  // source and unit are free text (a file path may be long): not limited here.
  return Checker(why)
      .id("asset_group", s.asset_group())
      .names("channel_names", s.channel_names(), kMaxChannels)
      .result();
}

Refusal check_limits(const causal_twin::ConditionVector& s, std::string& why) {
  return Checker(why)
      .id("asset_group", s.asset_group())
      .id("feature", s.feature())
      .names("channel_names", s.channel_names(), kMaxChannels)
      .sequence("values", s.values().size(), kMaxChannels)
      .result();
}

Refusal check_limits(const causal_twin::CausalFactorBatch& s, std::string& why) {
  Checker c(why);
  c.id("asset_group", s.asset_group())
      .enumeration("kind", static_cast<std::uint32_t>(s.kind()), 3)
      .enumeration("time_scale", static_cast<std::uint32_t>(s.time_scale()), 2)
      .id("feature", s.feature())
      .id("order_source", s.order_source())
      .sequence("outcomes", s.outcomes().size(), kMaxChannels);
  for (const auto& o : s.outcomes()) {
    c.id("outcome_name", o.outcome_name())
        .sequence("factor_names", o.factor_names().size(), kMaxFactors)
        .sequence("factors", o.factors().size(), kMaxFactors)
        .sequence("factor_std", o.factor_std().size(), kMaxFactors)
        .sequence("factor_covariance", o.factor_covariance().size(), kMaxFactors * (kMaxFactors + 1) / 2);
  }
  return c.result();
}

Refusal check_limits(const causal_twin::CausalFactorSet& s, std::string& why) {
  Checker c(why);
  c.id("asset_group", s.asset_group())
      .enumeration("time_scale", static_cast<std::uint32_t>(s.time_scale()), 2)
      .sequence("batches", s.batches().size(), kMaxFactorSetBatches);
  if (const Refusal r = c.result(); r != Refusal::None) return r;
  // Each batch as it would be checked alone (the readers hand them on one by one).
  for (const auto& b : s.batches()) {
    if (const Refusal r = check_limits(b, why); r != Refusal::None) return r;
  }
  return Refusal::None;
}

Refusal check_limits(const causal_twin::Alarm& s, std::string& why) {
  return Checker(why)
      .id("alarm_id", s.alarm_id())
      .id("asset_group", s.asset_group())
      .id("channel_name", s.channel_name())
      .id("kind", s.kind())
      .id("category", s.category())
      .id("root_cause_name", s.root_cause_name())
      .id("next_level", s.next_level())
      .enumeration("severity", static_cast<std::uint32_t>(s.severity()), 3)
      .enumeration("state", static_cast<std::uint32_t>(s.state()), 3)
      .sequence("factor_names", s.factor_names().size(), kMaxChannels)
      .sequence("factor_baseline", s.factor_baseline().size(), kMaxChannels)
      .sequence("factor_now", s.factor_now().size(), kMaxChannels)
      .result();
}

Refusal check_limits(const causal_twin::Prognosis& s, std::string& why) {
  return Checker(why)
      .id("asset_group", s.asset_group())
      .id("level", s.level())
      .id("channel_name", s.channel_name())
      .id("alarm_id", s.alarm_id())
      .result();
}

Refusal check_limits(const causal_twin::AssetStatus& s, std::string& why) {
  return Checker(why)
      .id("asset_group", s.asset_group())
      .id("state", s.state())
      .id("root_cause_name", s.root_cause_name())
      .enumeration("worst_severity", static_cast<std::uint32_t>(s.worst_severity()), 3)
      .result();
}

Refusal check_limits(const causal_twin::Recommendation& s, std::string& why) {
  return Checker(why)
      .id("recommendation_id", s.recommendation_id())
      .id("alarm_id", s.alarm_id())
      .id("asset_group", s.asset_group())
      .id("answer_kind", s.answer_kind())
      .id("action_kind", s.action_kind())
      .id("act_on_name", s.act_on_name())
      .id("order_source", s.order_source())
      .result();
}

Refusal check_limits(const causal_twin::WhatIfRequest& s, std::string& why) {
  return Checker(why).id("request_id", s.request_id()).id("asset_group", s.asset_group()).result();
}

Refusal check_limits(const causal_twin::AlarmAction& s, std::string& why) { return check_alarm_action(s, why); }

Refusal check_limits(const causal_twin::AlarmActionResult& s, std::string& why) { return check_alarm_action(s, why); }

Refusal check_limits(const causal_twin::WhatIfReply& s, std::string& why) {
  return Checker(why)
      .id("request_id", s.request_id())
      .id("asset_group", s.asset_group())
      .id("answer_kind", s.answer_kind())
      .sequence("effect_immediate", s.effect_immediate().size(), kMaxChannels)
      .sequence("effect_steady_state", s.effect_steady_state().size(), kMaxChannels)
      .sequence("effect_low", s.effect_low().size(), kMaxChannels)
      .sequence("effect_high", s.effect_high().size(), kMaxChannels)
      .sequence("effect_median", s.effect_median().size(), kMaxChannels)
      .sequence("effect_percent", s.effect_percent().size(), kMaxChannels)
      .sequence("effect_percent_low", s.effect_percent_low().size(), kMaxChannels)
      .sequence("effect_percent_high", s.effect_percent_high().size(), kMaxChannels)
      .names("channel_names", s.channel_names(), kMaxChannels)
      .result();
}

Refusal check_limits(const causal_twin::Intervention& s, std::string& why) {
  return Checker(why)
      .id("request_id", s.request_id())
      .id("asset_group", s.asset_group())
      .id("recommendation_id", s.recommendation_id())
      .id("approved_by", s.approved_by())
      .result();
}

Refusal check_limits(const causal_twin::InterventionOutcome& s, std::string& why) {
  return Checker(why)
      .id("request_id", s.request_id())
      .id("asset_group", s.asset_group())
      .id("recommendation_id", s.recommendation_id())
      .id("status", s.status())
      .result();
}

namespace {
std::atomic<std::uint64_t> g_refusals{0};
}

void note_refusal(const std::string& type_name, Refusal reason, const std::string& why) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, Refusal>, std::uint64_t> seen;
  ++g_refusals;
  auto& m = metrics::process_metrics();
  m.counter("dds_samples_refused_total",
            "Received samples refused before use: undecodable, or an id, enum or sequence outside its limit",
            {{"type", type_name}, {"reason", refusal_name(reason)}})
      .inc();
  std::uint64_t n = 0;
  {
    std::lock_guard<std::mutex> lock(mutex);
    n = ++seen[{type_name, reason}];
  }
  if (n == 1 || n % 1000 == 0) {
    spdlog::warn("refused a {} sample ({}): {}; {} refused for this reason so far (counted in "
                 "dds_samples_refused_total)",
                 type_name, refusal_name(reason), why, n);
  }
}

std::uint64_t refusals_total() { return g_refusals.load(); }

}  // namespace causal::dds
