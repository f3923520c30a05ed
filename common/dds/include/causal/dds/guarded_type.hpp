// GuardedPubSubType<PubSubType>: the generated type support with the two places a received sample could end
// the process closed, and the limits of sample_limits.hpp checked before a service sees a sample. Every
// topic a causal::dds::Participant creates uses it (Participant::topic), so no service can forget it.
//
// What the generated code (fastddsgen 2.3, Fast CDR 1.0) did with hostile bytes:
//  * getKey serialised the key into a buffer of getKeyMaxCdrSerializedSize() bytes (255 per string): a longer
//    asset group or request id threw NotEnoughMemoryException on Fast DDS's receive thread (a Fast DDS 2.9
//    writer sends no key hash with ALIVE data, so every reader computes it) -> std::terminate. It also shared
//    that buffer between threads.
//  * deserialize caught only NotEnoughMemoryException: a bool byte other than 0/1 or a bad encapsulation
//    (BadParamException) escaped the same way.
// Here the key hash is computed over a buffer of the key's real size (the same bytes and MD5 as the
// generated code, so the instance handles on the wire do not change), decoding errors of any kind are a
// refusal, and a sample outside the limits is a refusal. Fast DDS drops a sample whose deserialize fails
// (ReadTakeCommand removes it from the history), so a refused sample never reaches take().
//
// Each refused sample is counted once (note_refusal): a reader first decodes a received sample to compute its
// key (DataReaderHistory's compute_key_for_change: deserialize, then getKey on the same object), and the
// refusal is counted in that getKey; the second decode at take() fails again silently. Refused samples all
// get one reserved instance handle, so hostile keys cannot use up the reader's max_instances.
#pragma once

#include "causal/dds/sample_limits.hpp"

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>
#include <fastdds/rtps/common/InstanceHandle.h>
#include <fastdds/rtps/common/SerializedPayload.h>
#include <fastrtps/utils/md5.h>

#include <algorithm>
#include <cstdint>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

namespace causal::dds {

// The instance handle every refused sample is filed under (no MD5 of a real key equals it in practice).
inline eprosima::fastrtps::rtps::InstanceHandle_t refused_sample_handle() {
  eprosima::fastrtps::rtps::InstanceHandle_t h;
  for (std::size_t i = 0; i < 16; ++i) h.value[i] = 0xA5;
  return h;
}

template <typename Base>
class GuardedPubSubType : public Base {
 public:
  using Sample = typename Base::type;

  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    std::string why;
    Refusal r = Refusal::None;
    try {
      if (!Base::deserialize(payload, data)) {
        r = Refusal::Malformed;
        why = "truncated or oversized field";
      }
    } catch (const eprosima::fastcdr::exception::Exception& e) {
      r = Refusal::Malformed;
      why = e.what();
    } catch (const std::bad_alloc&) {
      r = Refusal::Malformed;
      why = "a sequence length beyond memory";
    } catch (const std::length_error&) {
      r = Refusal::Malformed;
      why = "a sequence length beyond std::vector";
    }
    if (r == Refusal::None) {
      const Sample& s = *static_cast<const Sample*>(data);
      if (key_bytes(s) > Sample::getKeyMaxCdrSerializedSize()) {
        r = Refusal::KeyTooLong;
        why = "key of " + std::to_string(key_bytes(s)) + " bytes (at most " + std::to_string(kMaxIdBytes) +
              " per id)";
      } else {
        r = check_limits(s, why);
      }
    }
    last_refused() = {r == Refusal::None ? nullptr : data, r, why};
    return r == Refusal::None;
  }

  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5) override {
    auto& refused = last_refused();
    if (refused.object == data && data != nullptr) {
      // The decode just before failed: this is the receive path (compute_key_for_change). Count it once.
      note_refusal(this->getName(), refused.reason, refused.why);
      refused = {};
      *handle = refused_sample_handle();
      return true;
    }
    try {
      hash_key(*static_cast<const Sample*>(data), handle, force_md5);
    } catch (const std::exception& e) {
      // Not reached with Fast CDR's growing buffer; refuse rather than end the process.
      note_refusal(this->getName(), Refusal::Malformed, std::string("key hash: ") + e.what());
      *handle = refused_sample_handle();
    }
    return true;
  }

 private:
  struct RefusedDecode {
    const void* object = nullptr;
    Refusal reason = Refusal::None;
    std::string why;
  };
  // Per thread: the decode and the key computation of one received sample run back to back on one thread.
  static RefusedDecode& last_refused() {
    static thread_local RefusedDecode r;
    return r;
  }

  // The key, serialised as the generated getKey does (plain CDR, big endian), into a zeroed buffer that is
  // made larger until the key fits. Zeroed: Fast CDR skips alignment padding without writing it, and the
  // generated code reused one buffer, so its hash of a key followed by padding (e.g. an asset group of 4k+2
  // bytes before the enums of CausalFactorBatch's key) depended on the keys hashed before.
  static std::size_t serialize_key(const Sample& s, std::vector<char>& buffer) {
    std::size_t capacity = std::max<std::size_t>(Sample::getKeyMaxCdrSerializedSize(), 16);
    while (true) {
      buffer.assign(capacity, 0);
      eprosima::fastcdr::FastBuffer fast(buffer.data(), buffer.size());
      eprosima::fastcdr::Cdr ser(fast, eprosima::fastcdr::Cdr::BIG_ENDIANNESS);
      try {
        s.serializeKey(ser);
        return ser.getSerializedDataLength();
      } catch (const eprosima::fastcdr::exception::NotEnoughMemoryException&) {
        capacity *= 4;  // the key is in memory, so this ends
      }
    }
  }
  static std::size_t key_bytes(const Sample& s) {
    std::vector<char> buffer;
    return serialize_key(s, buffer);
  }
  // The generated getKey's result for any key length (MD5 of the serialised key when the type's key can
  // exceed 16 bytes, else the bytes themselves), without its shared buffer.
  static void hash_key(const Sample& s, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5) {
    std::vector<char> buffer;
    const std::size_t n = serialize_key(s, buffer);
    const auto* bytes = reinterpret_cast<const unsigned char*>(buffer.data());
    if (force_md5 || Sample::getKeyMaxCdrSerializedSize() > 16) {
      MD5 md5;  // Fast DDS 2.9 declares it in the global namespace
      md5.init();
      md5.update(bytes, static_cast<unsigned int>(n));
      md5.finalize();
      for (int i = 0; i < 16; ++i) handle->value[i] = md5.digest[i];
    } else {
      for (std::size_t i = 0; i < 16; ++i) handle->value[i] = i < n ? bytes[i] : 0;
    }
  }
};

}  // namespace causal::dds
