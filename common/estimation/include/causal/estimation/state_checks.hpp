// Checks used by the restore() functions of the streaming estimators: a checkpoint records the parameters and
// the shape of the object that wrote it, and restoring it into an object built differently must fail with a
// message that names what differs (e.g. "checkpoint has lag order 2, this filter has 1") instead of resuming
// with state that means something else.
#pragma once

#include "causal/estimation/state_archive.hpp"

#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace causal::estimation {

namespace detail {

template <typename T>
std::string state_value_text(const T& v) {
  if constexpr (std::is_same_v<T, bool>) {
    return v ? "on" : "off";
  } else if constexpr (std::is_floating_point_v<T>) {
    std::ostringstream s;
    s.precision(17);  // round-trip precision: two different doubles never print alike
    s << v;
    return s.str();
  } else if constexpr (std::is_enum_v<T>) {
    return std::to_string(static_cast<long long>(v));
  } else if constexpr (std::is_arithmetic_v<T>) {
    return std::to_string(v);
  } else {
    return "'" + std::string(v) + "'";
  }
}

}  // namespace detail

// Reads a parameter written with StateWriter::put and throws StateError unless it equals `current` (bitwise equal
// for doubles: parameters are copied, never recomputed): "checkpoint has <what> <saved>, this <owner> has
// <current>".
template <typename T>
void expect_saved(StateReader& r, const std::string& what, const T& current, const std::string& owner) {
  const T saved = r.get<T>();
  bool same = saved == current;
  if constexpr (std::is_floating_point_v<T>) same = std::memcmp(&saved, &current, sizeof(T)) == 0;
  if (!same) {
    throw StateError("checkpoint has " + what + " " + detail::state_value_text(saved) + ", this " + owner + " has " +
                     detail::state_value_text(current));
  }
}

// Reads a vector of doubles into `out`, which must already have the size the checkpoint holds (the size
// follows from the object's shape); throws StateError naming `what` otherwise.
inline void read_same_size(StateReader& r, std::vector<double>& out, const std::string& what) {
  std::vector<double> v;
  r.read(v);
  if (v.size() != out.size()) {
    throw StateError("checkpoint: " + what + " has " + std::to_string(v.size()) + " values, this object needs " +
                     std::to_string(out.size()));
  }
  out = std::move(v);
}

}  // namespace causal::estimation
