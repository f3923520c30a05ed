// The simulated IMS variants' random draws (ims_variants*.cpp): our own uniform and normal draws on top of
// mt19937_64, whose output the standard fixes. The standard library's distributions may differ between
// implementations, and a variant must be the same on every platform.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>

namespace causal::testing {

class Draws {
 public:
  explicit Draws(std::uint64_t seed) : rng_(seed) {}
  double uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  std::size_t index(std::size_t lo, std::size_t hi) {  // [lo, hi)
    return lo + static_cast<std::size_t>(uniform() * static_cast<double>(hi - lo));
  }
  double normal() {  // Box-Muller
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::mt19937_64 rng_;
};

}  // namespace causal::testing
