// A message in its wire form (CDR, as Fast DDS-Gen's type support writes it) and back: for checkpoints that
// keep published messages to send them again after a restart.
#pragma once

#include <fastdds/rtps/common/SerializedPayload.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

namespace causal::dds {

template <typename PubSubType>
std::string to_cdr_bytes(const typename PubSubType::type& msg) {
  PubSubType type;
  auto* m = const_cast<typename PubSubType::type*>(&msg);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(m)());
  if (!type.serialize(m, &payload)) throw std::runtime_error("cannot serialize a message for a checkpoint");
  return std::string(reinterpret_cast<const char*>(payload.data), payload.length);
}

// False when the bytes are not a message of this type (a corrupted or foreign checkpoint).
template <typename PubSubType>
bool from_cdr_bytes(const std::string& bytes, typename PubSubType::type& msg) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::memcpy(payload.data, bytes.data(), bytes.size());
  payload.length = static_cast<std::uint32_t>(bytes.size());
  return type.deserialize(&payload, &msg);
}

}  // namespace causal::dds
