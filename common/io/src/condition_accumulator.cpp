// Streaming condition features: per-block two-pass moments merged with the pairwise update.
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "causal/io/condition_features.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_checks.hpp"
#include "causal/estimation/state_fields.hpp"
#include "moments.hpp"

namespace causal::io {

ConditionAccumulator::ConditionAccumulator(int channels) : channels_(channels) {
  if (channels < 1) {
    throw std::invalid_argument("ConditionAccumulator: channels must be >= 1, got " + std::to_string(channels));
  }
  reset();
}

void ConditionAccumulator::reset() {
  const auto g = static_cast<std::size_t>(channels_);
  count_ = 0;
  rejected_ = 0;
  for (auto* v : {&mean_, &m2_, &m3_, &m4_, &abs_sum_, &abs_comp_, &peak_}) v->assign(g, 0.0);
}

namespace {

// One channel's block moments and running |x| statistics (eqs. below): mean of the block, central sums b2..b4
// (two-pass), and the running peak and Neumaier-compensated sum of |x| carried across blocks.
struct ChannelBlock {
  double mb = 0.0, b2 = 0.0, b3 = 0.0, b4 = 0.0;
  double peak = 0.0, abs_sum = 0.0, abs_comp = 0.0;
};

// The per-value step of the second pass for one channel. Every variant below applies exactly this sequence to
// each channel's values in row order, so each channel's sums are rounded identically whichever variant runs.
inline void second_pass_step(double v, ChannelBlock& b) {
  const double d = v - b.mb;
  const double d2 = d * d;
  b.b2 += d2;
  b.b3 += d2 * d;
  b.b4 += d2 * d2;
  const double a = std::abs(v);
  b.peak = a > b.peak ? a : b.peak;
  // Neumaier-compensated sum of |x|: the stream may be long (many blocks).
  const double t = b.abs_sum + a;
  b.abs_comp += std::abs(b.abs_sum) >= a ? (b.abs_sum - t) + a : (a - t) + b.abs_sum;
  b.abs_sum = t;
}

// One channel's values, contiguous (x[0..n)). The running sums live in locals (ChannelBlock by value): as
// members they may alias x (both double), and the compiler then stores and reloads them every value.
ChannelBlock channel_block(const double* x, std::size_t n, ChannelBlock b) {
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i) s += x[i];
  b.mb = s / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) second_pass_step(x[i], b);
  return b;
}

// All G channels side by side, straight from the row-major block (no gather), when every value is finite:
// G independent dependency chains per pass instead of one (each compensated sum is a serial chain). Returns
// false, with `b` untouched, when a value is not finite (the caller then skips that row).
template <std::size_t G>
bool channels_side_by_side(const double* rows, std::size_t n, ChannelBlock* b) {
  std::array<double, G> s{};
  bool finite = true;
  for (std::size_t i = 0; i < n; ++i) {
    const double* row = rows + i * G;
    for (std::size_t c = 0; c < G; ++c) {
      finite = finite && std::isfinite(row[c]);
      s[c] += row[c];
    }
  }
  if (!finite) return false;
  std::array<ChannelBlock, G> local;
  for (std::size_t c = 0; c < G; ++c) {
    local[c] = b[c];
    local[c].mb = s[c] / static_cast<double>(n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double* row = rows + i * G;
    for (std::size_t c = 0; c < G; ++c) second_pass_step(row[c], local[c]);
  }
  for (std::size_t c = 0; c < G; ++c) b[c] = local[c];
  return true;
}

constexpr std::size_t kSideBySideMax = 8;

bool side_by_side(const double* rows, std::size_t n, std::size_t g, ChannelBlock* b) {
  switch (g) {
    case 1: return channels_side_by_side<1>(rows, n, b);
    case 2: return channels_side_by_side<2>(rows, n, b);
    case 3: return channels_side_by_side<3>(rows, n, b);
    case 4: return channels_side_by_side<4>(rows, n, b);
    case 5: return channels_side_by_side<5>(rows, n, b);
    case 6: return channels_side_by_side<6>(rows, n, b);
    case 7: return channels_side_by_side<7>(rows, n, b);
    case 8: return channels_side_by_side<8>(rows, n, b);
    default: return false;
  }
}

// Merges a block's moments into the accumulated ones (A = accumulated over na rows, B = the block of n_b rows);
// Pebay (2008), "Formulas for robust, one-pass parallel computation of covariances and arbitrary-order
// statistical moments", eqs. for M2..M4.
void merge_moments(const ChannelBlock& blk, double na, double n_b, double& mean, double& m2, double& m3, double& m4) {
  const double n = na + n_b;
  const double b2 = blk.b2, b3 = blk.b3, b4 = blk.b4;
  const double a2 = m2, a3 = m3, a4 = m4;
  const double delta = blk.mb - mean;
  const double dn = delta / n;
  const double dn2 = dn * dn;
  mean += n_b * dn;
  m2 = a2 + b2 + delta * dn * na * n_b;
  m3 = a3 + b3 + dn2 * delta * na * n_b * (na - n_b) + 3.0 * dn * (na * b2 - n_b * a2);
  m4 = a4 + b4 + dn2 * dn * delta * na * n_b * (na * na - na * n_b + n_b * n_b) +
       6.0 * dn2 * (na * na * b2 + n_b * n_b * a2) + 4.0 * dn * (na * b3 - n_b * a3);
}

}  // namespace

void ConditionAccumulator::add(const double* samples_row_major, std::size_t n_samples) {
  if (n_samples == 0) return;
  if (samples_row_major == nullptr) throw std::invalid_argument("ConditionAccumulator::add: null samples");
  const auto g = static_cast<std::size_t>(channels_);
  std::array<ChannelBlock, kSideBySideMax> fixed;
  std::vector<ChannelBlock> many(g > kSideBySideMax ? g : 0);
  ChannelBlock* blocks = g > kSideBySideMax ? many.data() : fixed.data();
  for (std::size_t c = 0; c < g; ++c) blocks[c] = ChannelBlock{0.0, 0.0, 0.0, 0.0, peak_[c], abs_sum_[c], abs_comp_[c]};
  std::size_t nb = n_samples;
  if (!side_by_side(samples_row_major, n_samples, g, blocks)) {
    // A non-finite value, or more channels than the side-by-side variants: gather the accepted rows
    // channel-major and run one channel at a time.
    block_.resize(n_samples * g);
    nb = 0;
    for (std::size_t i = 0; i < n_samples; ++i) {
      const double* row = samples_row_major + i * g;
      bool finite = true;
      for (std::size_t c = 0; c < g; ++c) finite = finite && std::isfinite(row[c]);
      if (!finite) {
        ++rejected_;
        continue;
      }
      for (std::size_t c = 0; c < g; ++c) block_[c * n_samples + nb] = row[c];
      ++nb;
    }
    if (nb == 0) return;
    for (std::size_t c = 0; c < g; ++c) blocks[c] = channel_block(block_.data() + c * n_samples, nb, blocks[c]);
  }
  const double na = static_cast<double>(count_);
  const double n_b = static_cast<double>(nb);
  for (std::size_t c = 0; c < g; ++c) {
    peak_[c] = blocks[c].peak;
    abs_sum_[c] = blocks[c].abs_sum;
    abs_comp_[c] = blocks[c].abs_comp;
    merge_moments(blocks[c], na, n_b, mean_[c], m2_[c], m3_[c], m4_[c]);
  }
  count_ += nb;
}

Eigen::VectorXd ConditionAccumulator::value(ConditionFeature feature) const {
  Eigen::VectorXd out = Eigen::VectorXd::Constant(channels_, std::numeric_limits<double>::quiet_NaN());
  if (count_ == 0) return out;
  const auto n = static_cast<double>(count_);
  for (int c = 0; c < channels_; ++c) {
    const auto k = static_cast<std::size_t>(c);
    switch (feature) {
      case ConditionFeature::Rms:
        // mean(x^2) = var + mean^2: both terms are >= 0, so no cancellation.
        out(c) = std::sqrt(m2_[k] / n + mean_[k] * mean_[k]);
        break;
      case ConditionFeature::MeanAbs:
        out(c) = (abs_sum_[k] + abs_comp_[k]) / n;
        break;
      case ConditionFeature::Kurtosis:
        out(c) = detail::kurtosis_from_sums(n, m2_[k], m4_[k], peak_[k]);
        break;
      case ConditionFeature::Peak:
        out(c) = peak_[k];
        break;
    }
  }
  return out;
}

template <class IO, class Self>
void ConditionAccumulator::fields(IO io, Self& a) {
  io.template as<std::uint64_t>(a.count_);
  io.template as<std::uint64_t>(a.rejected_);
  for (auto* v : {&a.mean_, &a.m2_, &a.m3_, &a.m4_, &a.abs_sum_, &a.abs_comp_, &a.peak_}) {
    io.same_size(*v, "condition accumulator moments");
  }
}

void ConditionAccumulator::save(estimation::StateWriter& w) const {
  w.begin("condition_accumulator", 1);
  w.put(static_cast<std::int32_t>(channels_));
  fields(estimation::SaveFields{w}, *this);
}

void ConditionAccumulator::restore(estimation::StateReader& r) {
  r.expect("condition_accumulator", 1);
  const auto g = r.get<std::int32_t>();
  if (g != channels_) {
    throw estimation::StateError("checkpoint has a condition accumulator of " + std::to_string(g) + " channels, this one has " +
                     std::to_string(channels_));
  }
  ConditionAccumulator a(channels_);
  fields(estimation::RestoreFields{r}, a);
  *this = std::move(a);
}

}  // namespace causal::io
