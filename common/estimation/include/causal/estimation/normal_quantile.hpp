// Quantile of the standard normal distribution, shared by the alarm thresholds and the effect intervals.
#pragma once

namespace causal::estimation {

// x with Phi(x) = p for p in (0, 1); throws std::invalid_argument otherwise. Acklam's rational
// approximation (relative error ~1e-9) refined by one Halley step on Phi(x) - p, so the result is accurate to
// machine level in both tails.
double normal_quantile(double p);

}  // namespace causal::estimation
