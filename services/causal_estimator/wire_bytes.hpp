// causal-estimator: DDS messages in their wire form (CDR, as Fast DDS-Gen's type support writes it), the form the
// checkpoint's resend list keeps them in.
#pragma once

#include <fastdds/rtps/common/SerializedPayload.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace causal::estimator {

// A message in its wire form (CDR, as Fast DDS-Gen's type support writes it), for the checkpoint's resend list.
template <typename PubSubType>
inline std::string to_bytes(const typename PubSubType::type& msg) {
  PubSubType type;
  auto* m = const_cast<typename PubSubType::type*>(&msg);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(m)());
  if (!type.serialize(m, &payload)) throw std::runtime_error("cannot serialize a message for the checkpoint");
  return std::string(reinterpret_cast<const char*>(payload.data), payload.length);
}

template <typename PubSubType>
inline bool from_bytes(const std::string& bytes, typename PubSubType::type& msg) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::memcpy(payload.data, bytes.data(), bytes.size());
  payload.length = static_cast<std::uint32_t>(bytes.size());
  return type.deserialize(&payload, &msg);
}

}  // namespace causal::estimator
