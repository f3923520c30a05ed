// Internal: shared helper of the batch and streaming condition features.
#pragma once

namespace causal::io::detail {

// Pearson kurtosis n*M4/M2^2 from central sums M2, M4 of n samples whose max |x| is peak; NaN when the
// variance is zero to rounding (constant signal: kurtosis undefined).
double kurtosis_from_sums(double n, double m2, double m4, double peak);

}  // namespace causal::io::detail
