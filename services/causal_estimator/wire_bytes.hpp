// causal-estimator: DDS messages in their wire form (CDR, as Fast DDS-Gen's type support writes it), the form the
// checkpoint's resend list keeps them in: the one CDR round trip of causal_dds (cdr_bytes.hpp) under the names
// this service's files use.
#pragma once

#include <string>

#include "causal/dds/cdr_bytes.hpp"

namespace causal::estimator {

template <typename PubSubType>
inline std::string to_bytes(const typename PubSubType::type& msg) {
  return dds::to_cdr_bytes<PubSubType>(msg);
}

template <typename PubSubType>
inline bool from_bytes(const std::string& bytes, typename PubSubType::type& msg) {
  return dds::from_cdr_bytes<PubSubType>(bytes, msg);
}

}  // namespace causal::estimator
