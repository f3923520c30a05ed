// Time gaps in a recording: where a run of snapshots (or feature rows) stops and starts again later.
//
// IMS-style recorders take a snapshot at a fixed interval (test 2: every 10 minutes) but real recordings stop
// for hours or days (maintenance, a full disk). Across such a stop the levels may shift although nothing is
// wrong, and no lag term may span it. Rule: an interval longer than `factor` x the median interval of the
// recording is a gap, and the row after it a discontinuity. The median (not the mean or the smallest) is the
// recorder's usual cadence even when a few intervals are long or a few snapshots are missing; factor 3 (the
// shipped default) tolerates one or two missed snapshots, which is jitter, not a stop.
#pragma once

#include <cstdint>
#include <vector>

namespace causal::io {

struct TimeGaps {
  std::int64_t median_interval_ns = 0;  // 0 for fewer than two rows
  std::vector<std::size_t> rows;        // rows i >= 1 with time_ns[i] - time_ns[i - 1] > factor x median interval
};

// time_ns must be strictly increasing (feature tables and IMS listings are checked on reading). Throws
// std::invalid_argument when factor is not finite or < 1 (an interval shorter than usual is never a gap).
TimeGaps find_time_gaps(const std::vector<std::int64_t>& time_ns, double factor);

}  // namespace causal::io
