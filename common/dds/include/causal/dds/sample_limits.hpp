// Limits every received sample must meet before any service uses it, checked by GuardedPubSubType
// (guarded_type.hpp) right after the bytes are decoded. A sample outside them is refused and counted
// (dds_samples_refused_total{type, reason}), never handed to a service.
//
// Why here and not in the IDL: the generated code budgets 255 bytes for every unbounded string in a key
// (getKeyMaxCdrSerializedSize) and serialised the key into a buffer of exactly that size; a longer asset group
// or request id threw NotEnoughMemoryException on Fast DDS's receive thread and ended the process. Bounded
// strings in the IDL would change the type (its TypeObject) and rebuild everything, and still leave every
// other field unchecked; the wire format here stays exactly what it was.
#pragma once

#include "causal_twin.h"

#include "causal/io/name_limits.hpp"

#include <cstddef>
#include <string>

namespace causal::dds {

// The longest id (asset group, channel name, alarm id, request or recommendation id, feature, level) a sample may
// carry: what the generated key code budgets for one string (the one name limit, causal/io/name_limits.hpp).
inline constexpr std::size_t kMaxIdBytes = io::kMaxNameBytes;
// The bound the IDL declares for channel lists and per-channel sequences (sequence<..., 64>), which the
// generated decoder does not enforce.
inline constexpr std::size_t kMaxChannels = io::kMaxChannels;
// The bound of one outcome's factor list (sequence<..., 1024>).
inline constexpr std::size_t kMaxFactors = 1024;
// The bound of a CausalFactorSet's batches (sequence<CausalFactorBatch, 4>).
inline constexpr std::size_t kMaxFactorSetBatches = 4;

// Why a sample was refused: the `reason` label of dds_samples_refused_total.
enum class Refusal { None, Malformed, KeyTooLong, IdTooLong, BadEnum, SequenceTooLong };
const char* refusal_name(Refusal r);

// The checks per type (ids at most kMaxIdBytes, enums in range, sequences within their IDL bound).
// `why` names the field on refusal.
Refusal check_limits(const causal_twin::VibrationFrame& s, std::string& why);
Refusal check_limits(const causal_twin::ConditionVector& s, std::string& why);
Refusal check_limits(const causal_twin::CausalFactorBatch& s, std::string& why);
Refusal check_limits(const causal_twin::CausalFactorSet& s, std::string& why);
Refusal check_limits(const causal_twin::Alarm& s, std::string& why);
Refusal check_limits(const causal_twin::Prognosis& s, std::string& why);
Refusal check_limits(const causal_twin::AssetStatus& s, std::string& why);
Refusal check_limits(const causal_twin::Recommendation& s, std::string& why);
Refusal check_limits(const causal_twin::WhatIfRequest& s, std::string& why);
Refusal check_limits(const causal_twin::WhatIfReply& s, std::string& why);
// Alarm actions: ids bounded, the action kind in range; the user and reason as ids (alarm-recommender refuses
// them longer than its own limit and counts it).
Refusal check_limits(const causal_twin::AlarmAction& s, std::string& why);
Refusal check_limits(const causal_twin::AlarmActionResult& s, std::string& why);
Refusal check_limits(const causal_twin::Intervention& s, std::string& why);
Refusal check_limits(const causal_twin::InterventionOutcome& s, std::string& why);

// Counts a refusal (dds_samples_refused_total{type, reason}) and logs it: the first of each (type, reason)
// and then every 1000th, so a flood cannot flood the log too. Thread-safe.
void note_refusal(const std::string& type_name, Refusal reason, const std::string& why);
// Refusals so far in this process (all types and reasons), for tests and summaries.
std::uint64_t refusals_total();

}  // namespace causal::dds
