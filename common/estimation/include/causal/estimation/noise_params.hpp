// Noise parameters of one outcome's random-walk state-space model:
//   x[n+1] = x[n] + w[n],  w ~ N(0, q I)      (process noise, factor units^2 per sample)
//   y_k[n] = h[n]^T x[n] + eps[n], eps ~ N(0, r) (measurement noise, channel units^2)
//   x[0] ~ N(0, p0 I)                          (prior of the state at the first sample)
#pragma once

#include <string>

namespace causal::estimation {

struct NoiseParams {
  double q = 1e-6;
  double r = 1e-2;
  double p0 = 1.0;
};

// Throws std::invalid_argument unless q >= 0, r > 0, p0 > 0, all finite. `what` prefixes the message
// (e.g. "noise[2]").
void validate_noise_params(const NoiseParams& noise, const std::string& what);

}  // namespace causal::estimation
