#include "causal/estimation/noise_params.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace causal::estimation {

void validate_noise_params(const NoiseParams& noise, const std::string& what) {
  auto fail = [&](const std::string& field, double v, const char* rule) {
    std::ostringstream os;
    os << what << "." << field << " = " << v << " is invalid: must be " << rule;
    throw std::invalid_argument(os.str());
  };
  if (!std::isfinite(noise.q) || noise.q < 0.0) fail("q", noise.q, "finite and >= 0");
  if (!std::isfinite(noise.r) || noise.r <= 0.0) fail("r", noise.r, "finite and > 0");
  if (!std::isfinite(noise.p0) || noise.p0 <= 0.0) fail("p0", noise.p0, "finite and > 0");
}

}  // namespace causal::estimation
