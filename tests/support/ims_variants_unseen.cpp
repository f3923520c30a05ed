// Two runs the alarm rules were not tuned on: see ims_variants_unseen.hpp.
#include "ims_variants_unseen.hpp"
#include "variant_draws.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

namespace causal::testing {
namespace {

constexpr std::int64_t kHour = 3600LL * 1000000000LL;
constexpr std::int64_t kDay = 24 * kHour;

}  // namespace

Variant make_relevelled_failure_variant(const BaseRun& base, std::uint64_t seed) {
  const RelevelledFailureRows at;
  const std::size_t n = at.plateau_end + at.final_rows;
  if (static_cast<std::size_t>(base.values.rows()) < n || n > base.healthy_end || base.values.cols() < 2)
    throw std::invalid_argument("relevelled_failure: the base run needs " + std::to_string(n) + " healthy rows");
  Draws draw(seed ^ 0xe5);
  const Eigen::Index g = base.values.cols();
  Variant v;
  v.name = "relevelled_failure";
  for (Eigen::Index c = 0; c < g; ++c) {
    v.channel_names.push_back(base.channel_names[static_cast<std::size_t>(c)] + " C1");
    v.channel_names.push_back(base.channel_names[static_cast<std::size_t>(c)] + " C2");
  }
  v.values.resize(static_cast<Eigen::Index>(n), 2 * g);
  // Post-gap factors: one per channel in [1.20, 1.45], the last channel at 1.44 (the "44 % above" channel).
  std::vector<double> relevel(static_cast<std::size_t>(2 * g));
  for (auto& f : relevel) f = draw.uniform(1.20, 1.45);
  relevel.back() = 1.44;
  const double final_c1[4] = {2.5, 2.8, 3.0, 3.3}, final_c2[4] = {1.8, 2.0, 2.1, 2.2};
  std::int64_t shift = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i == at.first_gap) shift += 6 * kDay;
    if (i == at.plateau_end) shift += kHour;
    v.time_ns.push_back(base.time_ns[i] + shift);
    v.source_row.push_back(i);
    for (Eigen::Index c = 0; c < g; ++c) {
      const auto r = static_cast<Eigen::Index>(i);
      const double noise2 = std::exp(0.01 * draw.normal());
      double f1 = 1.0, f2 = 1.0;
      if (i >= at.first_gap) {
        f1 = relevel[static_cast<std::size_t>(2 * c)];
        f2 = relevel[static_cast<std::size_t>(2 * c + 1)];
      }
      double w1 = 1.0, w2 = 1.0;  // the failure of bearing 1, on top of its post-gap level
      if (c == base.failing_channel && i >= at.rise) {
        const std::size_t k = i - at.rise;
        const double plateau = draw.uniform(1.50, 1.60);
        if (i >= at.plateau_end) {
          w1 = final_c1[i - at.plateau_end];
          w2 = final_c2[i - at.plateau_end];
        } else {
          const double up = std::min(1.0, static_cast<double>(k + 1) / 3.0);  // 3 snapshots of rise
          w1 = 1.0 + up * (plateau - 1.0);
          w2 = 1.0 + up * 0.35;
        }
      }
      v.values(r, 2 * c) = base.values(r, c) * f1 * w1;
      v.values(r, 2 * c + 1) = base.values(r, c) * noise2 * f2 * w2;
    }
  }
  v.healthy_end = at.rise;
  v.failing_channels = {2 * base.failing_channel, 2 * base.failing_channel + 1};
  v.injections.push_back({at.first_gap, -1, 1.0, 6 * kDay});
  v.injections.push_back({at.rise, 2 * base.failing_channel, 1.55, 0});
  v.injections.push_back({at.plateau_end, 2 * base.failing_channel, 2.5, kHour});
  v.description = "8 channels; 6-day gap at row 160, every channel x[1.20, 1.45] after it; bearing 1 C1 x1.5-1.6 "
                  "from row 340 for 10 h (C2 x1.35), 1-h gap, last 4 rows x2.5-3.3";
  return v;
}

Variant make_low_baseline_stretch_variant(const BaseRun& base) {
  if (base.values.cols() < 4 || static_cast<std::size_t>(base.values.rows()) <= base.healthy_end || base.healthy_end < 500)
    throw std::invalid_argument("low_baseline_stretch: needs IMS test 2's 4 channels and 500 healthy rows");
  Variant v = copy_of_base(base, "low_baseline_stretch");
  const Eigen::Index c = 3;  // Bearing 4: healthy to the end of test 2
  for (Eigen::Index i = 20; i < v.values.rows(); ++i) {
    double f = 1.0;
    if (i < 140) f = 0.92;                                                    // the low stretch of the baseline
    else if (i < 170) f = 0.92 + 0.08 * static_cast<double>(i - 139) / 30.0;  // back to its earlier level
    if (i >= 300 && i < 304) f *= 1.20;                                       // one short excursion
    v.values(i, c) *= f;
  }
  v.injections.push_back({20, static_cast<int>(c), 0.92, 0});
  v.injections.push_back({140, static_cast<int>(c), 1.0 / 0.92, 0});
  v.injections.push_back({300, static_cast<int>(c), 1.20, 0});
  v.description = "Bearing 4: baseline rows 20-139 8 % below its warm-up level, back to it by row 170, +20 % at rows 300-303";
  return v;
}

}  // namespace causal::testing
