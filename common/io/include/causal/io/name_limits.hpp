// The one limit on the names that enter from outside: asset groups and channel names (also features, alarm and
// request ids on the bus). Every edge checks against these (sensor-ingest's blocks, sensor-replay's channel
// files, every DDS reader through causal/dds/sample_limits.hpp), so a name is refused where it enters, with its
// reason counted, instead of being taken by one process and refused by the next.
//
// Why 255 bytes: the generated DDS key code budgets 255 bytes for one string (getKeyMaxCdrSerializedSize), and
// a longer asset group cannot be a key. File names derived from a name stay within the file system's 255
// (safe_file_component, file_names.hpp, shortens long names with a hash). Why 64 channels: the IDL's bound on
// channel lists (sequence<string, 64>). Std only (header-only), below every library that needs it.
#pragma once

#include <cstddef>
#include <string>

namespace causal::io {

inline constexpr std::size_t kMaxNameBytes = 255;
inline constexpr std::size_t kMaxChannels = 64;

// Why `name` cannot be used as an asset group or channel name, or nullptr when it can.
inline const char* name_problem(const std::string& name) {
  if (name.empty()) return "empty";
  if (name.size() > kMaxNameBytes) return "longer than 255 bytes";
  return nullptr;
}

}  // namespace causal::io
