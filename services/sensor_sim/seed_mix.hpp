// Seeds for sensor-sim's generators (svar_generator, level_plant): the SplitMix64 finaliser turns (seed, group,
// stream) into well-separated generator seeds, so neighbouring groups or streams do not draw correlated numbers.
#pragma once

#include <cstdint>

namespace causal::sim {

inline std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace causal::sim
