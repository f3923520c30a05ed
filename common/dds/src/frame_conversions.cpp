#include "causal/dds/frame_conversions.hpp"

#include <cmath>
#include <cstdio>

namespace causal::dds {

void to_frame(const FrameHeader& header, const Eigen::Ref<const Eigen::MatrixXd>& block, Eigen::Index first_row,
              Eigen::Index rows, causal_twin::VibrationFrame& frame) {
  const Eigen::Index g = block.cols();
  frame.asset_group(header.asset_group);
  frame.sequence_number(header.sequence);
  frame.first_sample_index(header.first_sample_index);
  frame.snapshot_index(header.snapshot_index);
  frame.first_sample_time_ns(header.first_sample_time_ns);
  frame.sample_rate_hz(header.sample_rate_hz);
  frame.channel_names(header.channel_names);
  frame.unit(header.unit);
  frame.samples_per_channel(static_cast<uint32_t>(rows));
  frame.discontinuity(header.discontinuity);
  frame.end_of_segment(header.end_of_segment);
  frame.source(header.source);
  auto& out = frame.samples();
  out.resize(static_cast<std::size_t>(rows * g));
  // Sample-major (row-major) layout: samples[n * G + g].
  Eigen::Map<RowMajorMatrix>(out.data(), rows, g) = block.middleRows(first_row, rows);
}

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

std::string check_channels(std::size_t g) {
  if (g == 0) return "no channel names";
  if (g > InputLimits::kMaxChannels) {
    return std::to_string(g) + " channels, at most " + std::to_string(InputLimits::kMaxChannels) + " allowed";
  }
  return {};
}

std::string check_time(const char* field, std::int64_t t) {
  if (t < InputLimits::kMinTimeNs || t > InputLimits::kMaxTimeNs) {
    return std::string(field) + " " + std::to_string(t) +
           " is outside 1970-01-01..2100-01-01 UTC (ns since the Unix epoch; a time in s or us, or garbage?)";
  }
  return {};
}

std::string check_index(const char* field, std::uint64_t i) {
  if (i > InputLimits::kMaxIndex) {
    return std::string(field) + " " + std::to_string(i) + " is above 2^53 (" + std::to_string(InputLimits::kMaxIndex) +
           "): indices must stay exact and must not wrap";
  }
  return {};
}

}  // namespace

std::string validate_frame_header(std::size_t channels, double rate, std::int64_t first_sample_time_ns) {
  if (auto p = check_channels(channels); !p.empty()) return "frame has " + p;
  if (!std::isfinite(rate) || rate < InputLimits::kMinSampleRateHz || rate > InputLimits::kMaxSampleRateHz) {
    return "sample_rate_hz " + number(rate) + " is outside " + number(InputLimits::kMinSampleRateHz) + ".." +
           number(InputLimits::kMaxSampleRateHz) + " Hz";
  }
  return check_time("first_sample_time_ns", first_sample_time_ns);
}

std::string validate_frame(const causal_twin::VibrationFrame& frame) {
  const std::size_t g = frame.channel_names().size();
  if (auto p = validate_frame_header(g, frame.sample_rate_hz(), frame.first_sample_time_ns()); !p.empty()) return p;
  if (auto p = check_index("sequence_number", frame.sequence_number()); !p.empty()) return p;
  if (auto p = check_index("snapshot_index", frame.snapshot_index()); !p.empty()) return p;
  if (auto p = check_index("first_sample_index", frame.first_sample_index()); !p.empty()) return p;
  if (auto p = check_index("last sample index (first_sample_index + samples_per_channel)",
                           frame.first_sample_index() + frame.samples_per_channel());
      !p.empty()) {
    return p;
  }
  const std::size_t expected = static_cast<std::size_t>(frame.samples_per_channel()) * g;
  if (frame.samples().size() != expected) {
    return "samples has " + std::to_string(frame.samples().size()) + " values, expected samples_per_channel x G = " +
           std::to_string(expected);
  }
  return {};
}

Eigen::Map<const RowMajorMatrix> samples_view(const causal_twin::VibrationFrame& frame) {
  return Eigen::Map<const RowMajorMatrix>(frame.samples().data(),
                                          static_cast<Eigen::Index>(frame.samples_per_channel()),
                                          static_cast<Eigen::Index>(frame.channel_names().size()));
}

std::vector<std::string> channel_names(const causal_twin::VibrationFrame& frame) {
  return {frame.channel_names().begin(), frame.channel_names().end()};
}

void to_condition_vector(const ConditionHeader& header, const Eigen::Ref<const Eigen::VectorXd>& values,
                         causal_twin::ConditionVector& out) {
  out.asset_group(header.asset_group);
  out.feature(header.feature);
  out.snapshot_index(header.snapshot_index);
  out.time_ns(header.time_ns);
  out.channel_names(header.channel_names);
  out.values(std::vector<double>(values.data(), values.data() + values.size()));
  out.discontinuity(header.discontinuity);
}

std::string validate_condition_vector(const causal_twin::ConditionVector& in) {
  if (auto p = check_channels(in.channel_names().size()); !p.empty()) return "condition vector has " + p;
  if (auto p = check_time("time_ns", in.time_ns()); !p.empty()) return p;
  if (auto p = check_index("snapshot_index", in.snapshot_index()); !p.empty()) return p;
  if (in.values().size() != in.channel_names().size()) {
    return "condition vector has " + std::to_string(in.values().size()) + " values for " +
           std::to_string(in.channel_names().size()) + " channels";
  }
  // Non-finite values are not a malformed message: the estimator's input screen rejects them per channel
  // (counted, a data-quality event), so one bad channel does not cost the others their snapshot.
  return {};
}

Eigen::VectorXd values_of(const causal_twin::ConditionVector& in) {
  return Eigen::Map<const Eigen::VectorXd>(in.values().data(), static_cast<Eigen::Index>(in.values().size()));
}

}  // namespace causal::dds
