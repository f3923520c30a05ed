// The participant settings of the two-process DDS benchmarks (bench_raw_dds, bench_frame_layouts): the QoS and
// transport files and the domain of their options, no DDS-Security (they measure the open bus).
#pragma once

#include "causal/dds/participant.hpp"

#include <string>

namespace causal::bench {

template <typename Options>
causal::dds::DdsSettings dds_settings(const Options& o, const std::string& name) {
  causal::dds::DdsSettings s;
  s.profile_files = {o.qos, o.transport};
  s.domain_id = o.domain;
  s.participant_name = name;
  s.security_dir = "off";
  return s;
}

}  // namespace causal::bench
