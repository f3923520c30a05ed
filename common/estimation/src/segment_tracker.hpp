// Decides, sample by sample, whether the outcome updates can run: all G values finite and the M previous
// samples finite and in the same segment. Shared by the streaming filter and the batch passes so both classify
// every sample identically.
#pragma once

#include <cmath>

#include "causal/estimation/svar_kalman_filter.hpp"

namespace causal::estimation::detail {

// history: consecutive finite samples of the current segment before this one, capped at M (updated here).
inline SampleStatus classify_sample(const double* y, int channels, int lag_order, bool discontinuity,
                                    int& history) {
  for (int j = 0; j < channels; ++j) {
    if (!std::isfinite(y[j])) {
      history = 0;  // a non-finite value can never serve as a regressor: the next M samples re-fill history
      return SampleStatus::RejectedNonFinite;
    }
  }
  if (discontinuity) history = 0;  // this sample starts a new segment: earlier samples are not its lags
  const SampleStatus status = history >= lag_order ? SampleStatus::Updated : SampleStatus::WarmUp;
  if (history < lag_order) ++history;
  return status;
}

}  // namespace causal::estimation::detail
