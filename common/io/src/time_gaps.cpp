// Time gaps in a recording: see time_gaps.hpp.
#include "causal/io/time_gaps.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace causal::io {

TimeGaps find_time_gaps(const std::vector<std::int64_t>& time_ns, double factor) {
  if (!std::isfinite(factor) || factor < 1.0) throw std::invalid_argument("time gaps: factor must be finite and >= 1");
  TimeGaps gaps;
  if (time_ns.size() < 2) return gaps;
  std::vector<std::int64_t> intervals;
  intervals.reserve(time_ns.size() - 1);
  for (std::size_t i = 1; i < time_ns.size(); ++i) intervals.push_back(time_ns[i] - time_ns[i - 1]);
  std::vector<std::int64_t> sorted = intervals;
  const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  // Upper median for an even count: with as many long intervals as usual ones the recording has no cadence
  // to speak of, and the larger choice flags fewer gaps.
  gaps.median_interval_ns = *mid;
  const double limit = factor * static_cast<double>(gaps.median_interval_ns);
  for (std::size_t i = 0; i < intervals.size(); ++i) {
    if (static_cast<double>(intervals[i]) > limit) gaps.rows.push_back(i + 1);
  }
  return gaps;
}

}  // namespace causal::io
