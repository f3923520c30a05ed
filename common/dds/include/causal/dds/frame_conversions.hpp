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

// Checks the frame's shape (G >= 1 channel names, sample_rate > 0, samples.size() == N * G).
// Returns an empty string when valid, otherwise what is wrong.
std::string validate_frame(const causal_twin::VibrationFrame& frame);

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
// Empty string when the shape is valid (values.size() == channel_names.size() >= 1). Values may be non-finite:
// the consumer screens them per channel.
std::string validate_condition_vector(const causal_twin::ConditionVector& in);
Eigen::VectorXd values_of(const causal_twin::ConditionVector& in);

}  // namespace causal::dds
