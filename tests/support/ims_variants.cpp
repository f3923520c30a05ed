// Robustness variants of IMS test 2: see ims_variants.hpp.
#include "ims_variants.hpp"
#include "variant_draws.hpp"

#include "causal/io/feature_table.hpp"
#include "causal/io/time_format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <stdexcept>

namespace causal::testing {
namespace {

constexpr std::int64_t kHour = 3600LL * 1000000000LL;
constexpr std::int64_t kDay = 24 * kHour;

// The median interval between consecutive base rows (test 2: exactly 10 minutes).
std::int64_t median_interval(const std::vector<std::int64_t>& t) {
  if (t.size() < 2) throw std::invalid_argument("ims variants: the base run needs at least 2 rows");
  std::vector<std::int64_t> d;
  for (std::size_t i = 1; i < t.size(); ++i) d.push_back(t[i] - t[i - 1]);
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

void check_base(const BaseRun& base) {
  const auto n = static_cast<std::size_t>(base.values.rows());
  if (n != base.time_ns.size() || base.values.cols() != static_cast<Eigen::Index>(base.channel_names.size())) {
    throw std::invalid_argument("ims variants: base run shapes disagree");
  }
  if (base.healthy_end < 450 || base.healthy_end >= n) {
    throw std::invalid_argument("ims variants: the base run needs a healthy part of at least 450 rows and a degrading end");
  }
  if (base.failing_channel < 0 || base.failing_channel >= base.values.cols()) {
    throw std::invalid_argument("ims variants: failing channel out of range");
  }
}

}  // namespace

Variant copy_of_base(const BaseRun& base, const std::string& name) {
  check_base(base);
  Variant v;
  v.name = name;
  v.channel_names = base.channel_names;
  v.time_ns = base.time_ns;
  v.values = base.values;
  for (std::size_t i = 0; i < base.time_ns.size(); ++i) v.source_row.push_back(i);
  v.healthy_end = base.healthy_end;
  v.failing_channels = {base.failing_channel};
  return v;
}

BaseRun read_base_run(const std::string& merged_table_path) {
  const io::FeatureTable t = io::read_feature_table(merged_table_path);
  BaseRun b;
  b.channel_names = t.channel_names;
  b.time_ns = t.time_ns;
  b.values = t.values;
  return b;
}

Variant make_gaps_variant(const BaseRun& base, std::uint64_t seed) {
  Draws draw(seed ^ 0xa1);
  Variant v = copy_of_base(base, "gaps");
  // Three stops inside the healthy part, each with at least 140 healthy rows after the last one (as many as
  // the shipped warm-up + baseline), so a detector that re-learns after a gap has the room it has at the start.
  const std::size_t rows[3] = {draw.index(140, 160), draw.index(240, 260), draw.index(340, 360)};
  const std::int64_t gaps[3] = {4 * kHour + static_cast<std::int64_t>(draw.uniform() * 2.0 * kHour), 6 * kDay,
                                30 * kHour};
  std::int64_t shift_ns = 0;
  const auto g = base.values.cols();
  for (int s = 0; s < 3; ++s) {
    shift_ns += gaps[s];
    for (Eigen::Index c = 0; c < g; ++c) {
      const double f = draw.uniform(1.15, 1.20);
      v.values.block(static_cast<Eigen::Index>(rows[s]), c, v.values.rows() - static_cast<Eigen::Index>(rows[s]), 1) *= f;
      v.injections.push_back({rows[s], static_cast<int>(c), f, c == 0 ? gaps[s] : 0});
    }
    for (std::size_t i = rows[s]; i < v.time_ns.size(); ++i) v.time_ns[i] += gaps[s];
  }
  char text[256];
  std::snprintf(text, sizeof text,
                "gaps of %.1f h at row %zu, 6 days at row %zu, 30 h at row %zu; every channel x[1.15, 1.20] after each",
                static_cast<double>(gaps[0]) / static_cast<double>(kHour), rows[0], rows[1], rows[2]);
  v.description = text;
  return v;
}

Variant make_steps_variant(const BaseRun& base, std::uint64_t seed) {
  Draws draw(seed ^ 0xb2);
  Variant v = copy_of_base(base, "steps");
  std::vector<int> healthy;
  for (int c = 0; c < base.values.cols(); ++c) {
    if (c != base.failing_channel) healthy.push_back(c);
  }
  const int first = healthy[draw.index(0, healthy.size())];
  healthy.erase(std::find(healthy.begin(), healthy.end(), first));
  const int second = healthy[draw.index(0, healthy.size())];
  const std::size_t rows[2] = {draw.index(180, 220), draw.index(330, 370)};
  const int channels[2] = {first, second};
  std::string text = "operating changes:";
  for (int s = 0; s < 2; ++s) {
    const double f = draw.uniform(1.20, 1.40);
    const auto r = static_cast<Eigen::Index>(rows[s]);
    v.values.block(r, channels[s], v.values.rows() - r, 1) *= f;
    v.injections.push_back({rows[s], channels[s], f, 0});
    char one[128];
    std::snprintf(one, sizeof one, " %s x%.3f from row %zu", base.channel_names[static_cast<std::size_t>(channels[s])].c_str(),
                  f, rows[s]);
    text += one;
  }
  v.description = text;
  return v;
}

Variant make_eight_channel_variant(const BaseRun& base, std::uint64_t seed) {
  Draws draw(seed ^ 0xc3);
  Variant v = copy_of_base(base, "eight_channels");
  const Eigen::Index n = base.values.rows(), g = base.values.cols();
  v.values.resize(n, 2 * g);
  v.channel_names.clear();
  for (Eigen::Index c = 0; c < g; ++c) {
    v.channel_names.push_back(base.channel_names[static_cast<std::size_t>(c)] + " C1");
    v.channel_names.push_back(base.channel_names[static_cast<std::size_t>(c)] + " C2");
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index c = 0; c < g; ++c) {
      v.values(i, 2 * c) = base.values(i, c);
      v.values(i, 2 * c + 1) = base.values(i, c) * std::exp(0.01 * draw.normal());
    }
  }
  v.failing_channels = {2 * base.failing_channel, 2 * base.failing_channel + 1};
  v.description = "two sensors per bearing: C1 = base, C2 = base x exp(N(0, 0.01^2))";
  return v;
}

Variant make_eight_channel_gaps_variant(const BaseRun& base, std::uint64_t seed) {
  Variant v = make_gaps_variant(base, seed);
  const Variant eight = make_eight_channel_variant(base, seed);
  const Eigen::Index n = v.values.rows(), g = v.values.cols();
  Eigen::MatrixXd values(n, 2 * g);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index c = 0; c < g; ++c) {
      // Both sensors of a bearing carry the gap's level step of that bearing; C2 keeps its own noise.
      const double step = v.values(i, c) / base.values(i, c);
      values(i, 2 * c) = eight.values(i, 2 * c) * step;
      values(i, 2 * c + 1) = eight.values(i, 2 * c + 1) * step;
    }
  v.name = "eight_channels_gaps";
  v.values = values;
  v.channel_names = eight.channel_names;
  v.failing_channels = eight.failing_channels;
  v.description = "two sensors per bearing, with " + v.description;
  return v;
}

Variant make_stretched_variant(const BaseRun& base, std::uint64_t seed, std::size_t total_rows) {
  check_base(base);
  const std::size_t n = base.time_ns.size(), h = base.healthy_end;
  const std::size_t tail = n - h;
  if (total_rows < n) throw std::invalid_argument("ims variants: cannot stretch to fewer rows than the base has");
  Draws draw(seed ^ 0xd4);
  // Healthy path: 0 .. h-1 forward, then round trips h-1 -> h-1-s -> h-1 that end where the degrading part
  // begins. The extra rows E = total - n are split over k round trips of 2 s_i rows, s_i <= h - 1; an odd E
  // repeats the last healthy row once.
  const std::size_t extra = total_rows - n;
  const std::size_t half = extra / 2;
  const std::size_t k = half == 0 ? 0 : (half + (h - 2)) / (h - 1);
  std::vector<std::size_t> path;
  for (std::size_t i = 0; i < h; ++i) path.push_back(i);
  for (std::size_t trip = 0; trip < k; ++trip) {
    const std::size_t s = half / k + (trip < half % k ? 1 : 0);
    for (std::size_t j = 1; j <= s; ++j) path.push_back(h - 1 - j);
    for (std::size_t j = s; j-- > 0;) path.push_back(h - 1 - j);
  }
  if (extra % 2 == 1) path.push_back(h - 1);
  for (std::size_t i = h; i < n; ++i) path.push_back(i);

  Variant v;
  v.name = "stretched";
  v.channel_names = base.channel_names;
  const Eigen::Index g = base.values.cols();
  v.values.resize(static_cast<Eigen::Index>(path.size()), g);
  const std::int64_t step = median_interval(base.time_ns);
  for (std::size_t r = 0; r < path.size(); ++r) {
    v.source_row.push_back(path[r]);
    v.time_ns.push_back(base.time_ns.front() + static_cast<std::int64_t>(r) * step);
    const bool repeated = r >= h && r < path.size() - tail;
    for (Eigen::Index c = 0; c < g; ++c) {
      const double x = base.values(static_cast<Eigen::Index>(path[r]), c);
      v.values(static_cast<Eigen::Index>(r), c) = repeated ? x * std::exp(0.005 * draw.normal()) : x;
    }
  }
  v.healthy_end = path.size() - tail;
  v.failing_channels = {base.failing_channel};
  v.injections.push_back({h, -1, 1.0, 0});
  char text[160];
  std::snprintf(text, sizeof text, "%zu snapshots: healthy part walked back and forth to row %zu, then the base's last %zu rows",
                path.size(), v.healthy_end, tail);
  v.description = text;
  return v;
}

Variant make_unchanged_variant(const BaseRun& base) {
  Variant v = copy_of_base(base, "unchanged");
  v.description = "IMS test 2 as recorded";
  return v;
}

Variant make_replicated_variant(const BaseRun& base, int copies, std::uint64_t seed, double noise) {
  check_base(base);
  if (copies < 1) throw std::invalid_argument("ims variants: copies must be >= 1");
  if (!(noise >= 0.0 && noise <= 0.1)) throw std::invalid_argument("ims variants: noise must be in [0, 0.1]");
  Draws draw(seed ^ 0x5eed);
  Variant v = copy_of_base(base, "replicated_" + std::to_string(copies));
  const Eigen::Index n = base.values.rows(), g = base.values.cols(), r = copies;
  v.values.resize(n, g * r);
  v.channel_names.clear();
  for (Eigen::Index j = 0; j < g; ++j)
    for (Eigen::Index c = 0; c < r; ++c)
      v.channel_names.push_back(base.channel_names[static_cast<std::size_t>(j)] + " C" + std::to_string(c + 1));
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < g; ++j)
      for (Eigen::Index c = 0; c < r; ++c) {
        // Stays positive: Box-Muller on 53-bit uniforms gives |z| <= sqrt(2 x 53 ln 2) = 8.57, so 1 + 0.1 z >= 0.14.
        v.values(i, j * r + c) = base.values(i, j) * (1.0 + 0.1 * static_cast<double>(c)) * (1.0 + noise * draw.normal());
      }
  v.failing_channels.clear();
  for (int c = 0; c < copies; ++c) v.failing_channels.push_back(base.failing_channel * copies + c);
  char text[160];
  std::snprintf(text, sizeof text, "%d copies per channel: copy c = base x (1 + 0.1 c) x (1 + %.3g N(0, 1)) per cell",
                copies, noise);
  v.description = text;
  return v;
}

std::vector<Variant> make_all_variants(const BaseRun& base, std::uint64_t seed) {
  return {make_gaps_variant(base, seed), make_steps_variant(base, seed), make_eight_channel_variant(base, seed),
          make_stretched_variant(base, seed), make_unchanged_variant(base)};
}

void write_variant_csv(const Variant& v, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path);
  for (const auto& name : v.channel_names) out << ',' << name;
  out << '\n';
  char cell[40];
  for (Eigen::Index i = 0; i < v.values.rows(); ++i) {
    out << io::format_utc(v.time_ns[static_cast<std::size_t>(i)]);
    for (Eigen::Index c = 0; c < v.values.cols(); ++c) {
      std::snprintf(cell, sizeof cell, ",%.17g", v.values(i, c));
      out << cell;
    }
    out << '\n';
  }
  if (!out) throw std::runtime_error("write failed: " + path);
}

}  // namespace causal::testing
