// IDL <-> Eigen conversions for raw data (vibration frames, condition vectors). The services never touch
// the generated sequences directly: they go through these functions.
#pragma once

#include "causal_twin.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace causal::dds {

struct FrameHeader {
  std::string asset_group;
  std::uint64_t sequence = 0;
  std::uint64_t first_sample_index = 0;
  std::uint64_t snapshot_index = 0;  // the source's snapshot (segment) number
  std::int64_t first_sample_time_ns = 0;
  double sample_rate_hz = 0.0;
  std::vector<std::string> channel_names;
  std::string unit;
  bool discontinuity = false;
  bool end_of_segment = false;
  std::string source;
};

// Fills `frame` from a header and rows [first_row, first_row + rows) of an N x G block.
void to_frame(const FrameHeader& header, const Eigen::Ref<const Eigen::MatrixXd>& block, Eigen::Index first_row,
              Eigen::Index rows, causal_twin::VibrationFrame& frame);

// Input limits: values no sensor produces, refused with a clear message instead of reaching
// the filters (a rate of 1e-300 Hz makes the sample period infinite, a time of INT64_MIN overflows every
// interval, an index of 2^64-16 wraps the next frame's index to 0 and looks like a restart).
struct InputLimits {
  // 1 sample per 11.6 days .. 100 MHz: slower is not a sampled signal, faster no vibration DAQ delivers.
  static constexpr double kMinSampleRateHz = 1e-6;
  static constexpr double kMaxSampleRateHz = 1e8;
  // 1970-01-01 .. 2100-01-01 UTC, ns since the Unix epoch: data times of real plants (IMS: 2004); negative or
  // far-future times are a wrong unit (s or us read as ns) or garbage.
  static constexpr std::int64_t kMinTimeNs = 0;
  static constexpr std::int64_t kMaxTimeNs = 4102444800LL * 1000000000LL;
  // 2^53: indices stay exact as doubles (CSV, JSON, plots) and an index + a frame never wraps; 2^53 samples at
  // 1 MHz last 285 years.
  static constexpr std::uint64_t kMaxIndex = 1ULL << 53;
  // The IDL's bound on channel names (sequence<string, 64>).
  static constexpr std::size_t kMaxChannels = 64;
};

// Checks the frame's shape (1..64 channel names, samples.size() == N * G) and the InputLimits of its rate, time
// and indices (sequence, first and last sample index, snapshot). Returns an empty string when valid, otherwise
// what is wrong, naming the field and its limit.
std::string validate_frame(const causal_twin::VibrationFrame& frame);
// The part of validate_frame a source can check before it numbers a block: channel count, rate and time.
std::string validate_frame_header(std::size_t channels, double sample_rate_hz, std::int64_t first_sample_time_ns);

// Read-only N x G view of the frame's samples (row-major storage, no copy). Call validate_frame first.
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
Eigen::Map<const RowMajorMatrix> samples_view(const causal_twin::VibrationFrame& frame);

std::vector<std::string> channel_names(const causal_twin::VibrationFrame& frame);

struct ConditionHeader {
  std::string asset_group;
  std::string feature;
  std::uint64_t snapshot_index = 0;
  std::int64_t time_ns = 0;
  std::vector<std::string> channel_names;
  bool discontinuity = false;
};

void to_condition_vector(const ConditionHeader& header, const Eigen::Ref<const Eigen::VectorXd>& values,
                         causal_twin::ConditionVector& out);
// Empty string when the shape is valid (values.size() == channel_names.size(), 1..64) and the time and snapshot
// index are within InputLimits. Values may be non-finite: the consumer screens them per channel.
std::string validate_condition_vector(const causal_twin::ConditionVector& in);
Eigen::VectorXd values_of(const causal_twin::ConditionVector& in);

}  // namespace causal::dds
