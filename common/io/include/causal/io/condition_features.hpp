// Condition features of a vibration snapshot, per channel: RMS, mean |x|, kurtosis, peak |x|.
// Definitions (population moments over the N accepted samples x_1..x_N of one channel):
//   rms      = sqrt( (1/N) sum x_i^2 )
//   meanabs  = (1/N) sum |x_i|
//   kurtosis = m4 / m2^2, m_p = (1/N) sum (x_i - mean)^p      (Pearson, NOT excess: a Gaussian gives 3)
//   peak     = max |x_i|
// These match the numpy definitions used for derived_per_file_stats_all984.csv (see the IMS README).
//
// Non-finite input: a sample row (all G channels of one instant) containing any NaN/Inf is rejected
// and counted, never used. Degenerate cases return NaN rather than throwing: every feature when no
// sample was accepted; kurtosis when a channel's variance is zero to rounding (constant signal).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace causal::estimation {
class StateWriter;
class StateReader;
}  // namespace causal::estimation

namespace causal::io {

enum class ConditionFeature { Rms, MeanAbs, Kurtosis, Peak };

// "rms", "meanabs", "kurtosis", "peak" (any case; also "mean_abs", "peakabs", "peak_abs").
[[nodiscard]] std::optional<ConditionFeature> parse_condition_feature(std::string_view name);
// "rms", "meanabs", "kurtosis", "peak".
std::string to_string(ConditionFeature feature);
// Column suffix of that feature in derived_per_file_stats_all984.csv: "_rms", "_meanabs", "_kurtosis",
// "_peakabs" (pass it to read_feature_table()).
std::string derived_column_suffix(ConditionFeature feature);

// Batch computation, one value per column of samples (N x G). Two-pass central moments.
Eigen::VectorXd compute_condition_feature(const Eigen::Ref<const Eigen::MatrixXd>& samples,
                                          ConditionFeature feature);

// Streaming version: the frames of one snapshot arrive in blocks; add them, then read value().
// Each block's moments are computed two-pass and merged with the pairwise update of Chan et al. /
// Pebay (2008), so the result equals the batch computation to rounding, whatever the block sizes.
class ConditionAccumulator {
 public:
  explicit ConditionAccumulator(int channels);  // channels >= 1, else std::invalid_argument

  // n_samples rows of `channels` values each, sample-major: samples_row_major[i * channels + g].
  // Rows with a non-finite value are skipped and counted in rejected().
  void add(const double* samples_row_major, std::size_t n_samples);

  int channels() const noexcept { return channels_; }
  std::size_t count() const noexcept { return count_; }        // accepted sample rows
  std::size_t rejected() const noexcept { return rejected_; }  // skipped (non-finite) sample rows
  Eigen::VectorXd value(ConditionFeature feature) const;
  void reset();

  // Checkpoint (causal/estimation/state_archive.hpp), section "condition_accumulator": the channel count (restore
  // throws StateError when it differs, leaving the accumulator unchanged), the accepted and rejected row
  // counts and the per-channel running moments, compensated |x| sums and peaks, so that a window cut by a
  // restart yields the same features bit for bit.
  void save(estimation::StateWriter& w) const;
  void restore(estimation::StateReader& r);

 private:
  // The checkpoint's field list after the channel check (SaveFields / RestoreFields, state_fields.hpp).
  template <class IO, class Self>
  static void fields(IO io, Self& self);
  int channels_;
  std::size_t count_ = 0;
  std::size_t rejected_ = 0;
  // Per channel: running mean and central sums M2, M3, M4 (sum of (x - mean)^p), compensated sum |x|
  // (Neumaier: value + correction), max |x|.
  std::vector<double> mean_, m2_, m3_, m4_, abs_sum_, abs_comp_, peak_;
  std::vector<double> block_;  // scratch: accepted rows of the current block, channel-major
};

}  // namespace causal::io
