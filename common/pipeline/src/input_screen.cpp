#include "causal/pipeline/input_screen.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "causal/io/enum_names.hpp"

namespace causal::pipeline {

const char* to_string(ScreenLevel level) {
  return level == ScreenLevel::Sample ? "sample" : "condition";
}

const char* to_string(QualityEventKind kind) {
  static constexpr auto kNames =
      io::enum_names<QualityEventKind>({{QualityEventKind::NonFinite, "non_finite"},
                                        {QualityEventKind::OutOfRange, "out_of_range"},
                                        {QualityEventKind::Stuck, "stuck"},
                                        {QualityEventKind::ScaleChange, "scale_change"},
                                        {QualityEventKind::Recovered, "recovered"},
                                        {QualityEventKind::MachineStopped, "machine_stopped"},
                                        {QualityEventKind::MachineRunning, "machine_running"}});
  return kNames.name(kind, "unknown");
}

InputScreen::InputScreen(InputScreenParams params, int channels, ScreenLevel level)
    : params_(params), level_(level) {
  if (channels < 1) throw std::invalid_argument("input screen needs at least one channel");
  if (!(params_.max_abs_value > 0.0)) throw std::invalid_argument("input screen: max_abs_value must be > 0");
  if (params_.scale_window > 0) {
    if (!(params_.scale_collapse > 0.0 && params_.scale_collapse < 1.0) || !(params_.scale_explosion > 1.0) ||
        !std::isfinite(params_.scale_explosion)) {
      throw std::invalid_argument("input screen: need 0 < scale_collapse < 1 < scale_explosion (finite)");
    }
    if (params_.recovery_samples < params_.scale_window) {
      throw std::invalid_argument("input screen: recovery_samples must be >= scale_window");
    }
  }
  if ((params_.stuck_samples > 0 || params_.scale_window > 0) && params_.recovery_samples == 0) {
    throw std::invalid_argument("input screen: recovery_samples must be >= 1 when a channel can be quarantined");
  }
  channels_.resize(static_cast<std::size_t>(channels));
  counters_.resize(static_cast<std::size_t>(channels));
  for (auto& c : channels_) c.block.reserve(params_.scale_window);
}

void InputScreen::emit(std::vector<QualityEvent>& events, int j, QualityEventKind kind, std::uint64_t index,
                       std::uint64_t count, std::string reason) const {
  QualityEvent e;
  e.level = level_;
  e.channel = j;
  e.kind = kind;
  e.index = index;
  e.count = count;
  std::ostringstream os;
  os << to_string(level_) << " channel " << (j + 1) << " at " << (level_ == ScreenLevel::Sample ? "row " : "vector ")
     << index << ": " << reason;
  e.reason = os.str();
  events.push_back(std::move(e));
}

namespace {

// The least v >= 0 with fl(v / reference) >= limit: fl(v / reference) is monotone in v (IEEE division is correctly
// rounded), so "fl(v / reference) < limit" holds exactly for v below it. Found from fl(limit x reference) by
// stepping one double at a time (a step or two).
double first_not_below(double limit, double reference) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double t = limit * reference;
  while (t > 0.0 && !(std::nextafter(t, 0.0) / reference < limit)) t = std::nextafter(t, 0.0);
  while (t / reference < limit) t = std::nextafter(t, kInf);
  return t;
}

// The greatest v with fl(v / reference) <= limit: "fl(v / reference) > limit" holds exactly for v above it.
double last_not_above(double limit, double reference) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double u = std::min(limit * reference, std::numeric_limits<double>::max());
  while (u > 0.0 && !(u / reference <= limit)) u = std::nextafter(u, 0.0);
  while (std::nextafter(u, kInf) / reference <= limit) u = std::nextafter(u, kInf);
  return u;
}

}  // namespace

// The verdict of scale_block_bad's median test without the median: 1 bad, 0 good, -1 undecided.
// f(v) = v / reference is monotone (IEEE division is correctly rounded), so "f(v) < collapse" holds on a
// prefix of the sorted block and "f(v) > explosion" on a suffix; their lengths place the median's order
// statistics. With an even size the median 0.5 (a + b) of the middle pair lies in [a, b]; it is undecided
// only when a prefix or suffix ends exactly between a and b, and the caller then computes the median.
// The prefix and suffix are counted against the exact bounds of f (first_not_below, last_not_above), one
// comparison per value instead of a division (the divisions were about a third of the screen's time).
int InputScreen::scale_verdict_by_counting(ChannelState& c, double reference) const {
  const std::vector<double>& block = c.block;
  const std::size_t n = block.size();
  const std::size_t mid = n / 2;
  if (c.bounds_reference != reference) {
    c.bounds_reference = reference;
    c.collapse_below = first_not_below(params_.scale_collapse, reference);
    c.explosion_above = last_not_above(params_.scale_explosion, reference);
  }
  const double below = c.collapse_below, above = c.explosion_above;
  // Counted in doubles, two lanes each (whole numbers below 2^53: exact in any order), a form the compiler
  // vectorises; integer counts of a double comparison it does not (SSE2).
  double low0 = 0.0, low1 = 0.0, high0 = 0.0, high1 = 0.0;
  std::size_t i = 0;
  for (; i + 1 < n; i += 2) {
    low0 += block[i] < below ? 1.0 : 0.0;
    low1 += block[i + 1] < below ? 1.0 : 0.0;
    high0 += block[i] > above ? 1.0 : 0.0;
    high1 += block[i + 1] > above ? 1.0 : 0.0;
  }
  if (i < n) {
    low0 += block[i] < below ? 1.0 : 0.0;
    high0 += block[i] > above ? 1.0 : 0.0;
  }
  const auto low = static_cast<std::size_t>(low0 + low1), high = static_cast<std::size_t>(high0 + high1);
  // Sorted s[0..n): the median is s[mid] (odd n) or 0.5 (s[mid - 1] + s[mid]) (even n).
  const bool odd = n % 2 == 1;
  const std::size_t low_needed = mid + 1;  // low >= this: the median's ratio is below collapse
  const std::size_t high_needed = n - mid; // high >= this (odd) / > this (even): above explosion
  if (odd) return low >= low_needed || high >= high_needed ? 1 : 0;
  if (low >= low_needed || high > high_needed) return 1;           // b below, or a above
  if (low + 1 < low_needed && high < high_needed) return 0;        // a not below and b not above
  return -1;                                                       // the middle pair straddles a limit
}

// Closes a full scale block: sets the reference from the first block with a non-zero median, afterwards
// returns true when the block's median |x| is outside [collapse, explosion] x reference.
bool InputScreen::scale_block_bad(int j, ChannelState& c) {
  auto& block = c.block;
  ChannelQualityCounters& k = counters_[static_cast<std::size_t>(j)];
  if (k.reference_scale != 0.0) {
    // Once the reference is known only the verdict matters, and counting usually settles it exactly, at a
    // fraction of a selection's cost (the selection was ~9 % of the estimator's CPU time).
    if (const int verdict = scale_verdict_by_counting(c, k.reference_scale); verdict >= 0) {
      block.clear();
      return verdict == 1;
    }
  }
  const std::size_t mid = block.size() / 2;
  std::nth_element(block.begin(), block.begin() + static_cast<std::ptrdiff_t>(mid), block.end());
  double median = block[mid];
  if (block.size() % 2 == 0) {
    const double below = *std::max_element(block.begin(), block.begin() + static_cast<std::ptrdiff_t>(mid));
    median = 0.5 * (median + below);
  }
  block.clear();
  if (k.reference_scale == 0.0) {
    // A block of mostly zeros cannot be a reference (a dead channel is the stuck check's business).
    if (median > 0.0) k.reference_scale = median;
    return false;
  }
  const double ratio = median / k.reference_scale;
  return ratio < params_.scale_collapse || ratio > params_.scale_explosion;
}

// A value above scale_explosion x the calibration scale (and maybe the physical limit too): one out-of-range
// value, NaN; sudden_run of them in a row quarantine the channel (a scale change, not a spike).
double InputScreen::screen_exploded(int j, ChannelState& c, ChannelQualityCounters& k, double x, std::uint64_t index,
                                    std::vector<QualityEvent>& events) {
  ++k.out_of_range;
  if (c.last != Last::OutOfRange) {
    std::ostringstream os;
    os << "|" << x << "| above " << params_.scale_explosion << " x its calibration scale " << k.reference_scale
       << (std::abs(x) > params_.max_abs_value ? " and above the physical limit" : "") << ": replaced by NaN";
    emit(events, j, QualityEventKind::OutOfRange, index, k.out_of_range, os.str());
  }
  c.last = Last::OutOfRange;
  c.healthy_run = 0;
  if (++c.high_run >= params_.sudden_run && params_.sudden_run > 0 && !k.quarantined) {
    k.quarantined = true;
    std::ostringstream os;
    os << c.high_run << " values in a row above " << params_.scale_explosion << " x its calibration scale "
       << k.reference_scale << ": quarantined";
    emit(events, j, QualityEventKind::ScaleChange, index, ++k.scale_change, os.str());
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double InputScreen::screen_value(int j, double x, std::uint64_t index, std::vector<QualityEvent>& events) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  ChannelState& c = channels_[static_cast<std::size_t>(j)];
  ChannelQualityCounters& k = counters_[static_cast<std::size_t>(j)];
  ++k.screened;
  if (!std::isfinite(x)) {
    ++k.non_finite;
    if (c.last != Last::NonFinite) {
      emit(events, j, QualityEventKind::NonFinite, index, k.non_finite, "non-finite value replaced by NaN");
    }
    c.last = Last::NonFinite;
    return kNaN;
  }
  const double high = params_.scale_explosion * k.reference_scale;
  const bool exploded = params_.scale_window > 0 && k.reference_scale > 0.0 && std::abs(x) > high;
  if (std::abs(x) > params_.max_abs_value && !exploded) {
    ++k.out_of_range;
    if (c.last != Last::OutOfRange) {
      std::ostringstream os;
      os << "|" << x << "| above the physical limit " << params_.max_abs_value << ": replaced by NaN";
      emit(events, j, QualityEventKind::OutOfRange, index, k.out_of_range, os.str());
    }
    c.last = Last::OutOfRange;
    return kNaN;
  }
  bool evidence = false;
  QualityEventKind cause = QualityEventKind::Stuck;
  std::string why;
  // Above the physical limit, the relative one or both: one out-of-range value either way.
  if (exploded) return screen_exploded(j, c, k, x, index, events);
  c.high_run = 0;
  c.last = Last::Good;

  // Health checks on the measurement itself.
  if (params_.stuck_samples > 0) {
    if (c.same_run > 0 && x == c.last_value) {
      ++c.same_run;
    } else {
      c.same_run = 1;
      c.last_value = x;
    }
    if (c.same_run >= params_.stuck_samples) {
      evidence = true;
      if (!k.quarantined) {
        std::ostringstream os;
        os << "stuck at " << x << " for " << c.same_run << " values: quarantined";
        why = os.str();
      }
    }
  }
  if (params_.scale_window > 0 && params_.sudden_run > 0 && k.reference_scale > 0.0) {
    c.low_run = std::abs(x) < params_.scale_collapse * k.reference_scale ? c.low_run + 1 : 0;
    if (c.low_run >= params_.sudden_run) {
      evidence = true;
      const bool constant = c.same_run >= c.low_run;
      if (!k.quarantined && why.empty()) {
        cause = constant ? QualityEventKind::Stuck : QualityEventKind::ScaleChange;
        std::ostringstream os;
        if (constant) os << "stuck at " << x << " for " << c.low_run << " values";
        else os << c.low_run << " values in a row";
        os << " below " << params_.scale_collapse << " x its calibration scale " << k.reference_scale
           << ": quarantined";
        why = os.str();
      }
    }
  }
  if (params_.scale_window > 0) {
    c.block.push_back(std::abs(x));
    if (c.block.size() >= params_.scale_window) {
      const double reference = k.reference_scale;
      if (scale_block_bad(j, c)) {
        evidence = true;
        if (!k.quarantined && why.empty()) {
          cause = QualityEventKind::ScaleChange;
          std::ostringstream os;
          os << "robust scale (median |x| over " << params_.scale_window << " values) left [" << params_.scale_collapse
             << ", " << params_.scale_explosion << "] x its calibration " << reference << ": quarantined";
          why = os.str();
        }
      }
    }
  }
  const bool was_quarantined = k.quarantined;
  if (!why.empty() && !was_quarantined) {
    k.quarantined = true;
    const std::uint64_t count = cause == QualityEventKind::Stuck ? ++k.stuck : ++k.scale_change;
    emit(events, j, cause, index, count, why);
  }
  if (evidence) {
    c.healthy_run = 0;
  } else if (++c.healthy_run >= params_.recovery_samples && k.quarantined) {
    k.quarantined = false;
    ++k.recovered;
    std::ostringstream os;
    os << c.healthy_run << " healthy values in a row: back in use";
    emit(events, j, QualityEventKind::Recovered, index, k.recovered, os.str());
    return x;  // the value that completed the recovery run is healthy
  }
  if (k.quarantined) {
    ++k.quarantined_values;
    return kNaN;
  }
  return x;
}

// The common case of screen_value, one channel at a time: from row `from`, the run of values that are finite, in
// range, on a channel in use and complete no stuck run, no sudden run and no scale block. Their state changes are
// exactly screen_value's (counted, the runs and the scale block extended) and they are kept; returns the first
// row that needs screen_value (or n). The channel's state lives in locals over the run (as members they may alias
// the rows, and the compiler would store and reload them every value): screen_value once per value was ~7 % of
// the estimator's CPU time, a loop of `step`s about a third of it, and the clean stretches below less again.
std::size_t InputScreen::screen_plain_run(std::size_t j, const double* rows, std::size_t from, std::size_t n) {
  ChannelState& c = channels_[j];
  ChannelQualityCounters& k = counters_[j];
  if (k.quarantined || from >= n) return from;
  const auto g = static_cast<std::size_t>(channels());
  const double max_abs = params_.max_abs_value, reference = k.reference_scale;
  const bool scaled = params_.scale_window > 0;
  const bool explosion_check = scaled && reference > 0.0;
  const double high = params_.scale_explosion * reference;
  const bool low_check = scaled && params_.sudden_run > 0 && reference > 0.0;
  const double low_limit = params_.scale_collapse * reference;
  const std::size_t stuck = params_.stuck_samples, sudden = params_.sudden_run;
  // Values that fit into the scale block without completing it (the completing one is screen_value's).
  std::size_t last = n;
  if (scaled) {
    const std::size_t room = c.block.size() + 1 < params_.scale_window ? params_.scale_window - 1 - c.block.size() : 0;
    last = std::min(n, from + room);
  }
  std::size_t same = c.same_run, low = c.low_run;
  double last_value = c.last_value;
  const std::size_t block_start = c.block.size();
  if (scaled) c.block.resize(block_start + (last - from));
  double* block = c.block.data() + block_start;
  // One value's step, as screen_value would take it; false when the value needs screen_value.
  const auto step = [&](std::size_t i) {
    const double x = rows[i * g + j];
    const double a = std::abs(x);
    if (!std::isfinite(x) || a > max_abs || (explosion_check && a > high)) return false;
    std::size_t next_same = same;
    if (stuck > 0) {
      next_same = same > 0 && x == last_value ? same + 1 : 1;
      if (next_same >= stuck) return false;
    }
    std::size_t next_low = low;
    if (low_check) {
      next_low = a < low_limit ? low + 1 : 0;
      if (next_low >= sudden) return false;
    }
    if (stuck > 0 && next_same == 1) last_value = x;  // a new run starts at x
    same = next_same;
    low = next_low;
    if (scaled) block[i - from] = a;
    return true;
  };
  // A live channel's values are nearly all "clean": finite, within both limits, unequal to the value before and
  // not below the collapse limit. Over a stretch of clean values each step only restarts the runs (same = 1 from
  // that value on, low = 0), so a stretch is judged by one branch-free pass (no chain from value to value but the
  // OR) and its end state set at once; a stretch with any other value goes through `step`, value by value.
  // Equal values (+0 and -0 included) always take `step`, so last_value is what the value-by-value loop keeps.
  double limit = std::numeric_limits<double>::max();  // also refuses +-inf; a NaN limit never refuses (as `>`)
  if (max_abs < limit) limit = max_abs;
  if (explosion_check && high < limit) limit = high;
  const bool check_same = stuck > 1;  // stuck_samples = 1: every value completes a run (step refuses it)
  const double low_limit_checked = low_check ? low_limit : -1.0;  // a < -1 never holds
  constexpr std::size_t kStretch = 64;
  std::size_t i = from;
  while (i < last && stuck != 1) {
    const std::size_t end = std::min(last, i + kStretch);
    double prev = check_same && same > 0 ? last_value : std::numeric_limits<double>::quiet_NaN();
    bool dirty = false;
    for (std::size_t u = i; u < end; ++u) {
      const double x = rows[u * g + j];
      const double a = std::abs(x);
      dirty |= (!(a <= limit)) | (check_same & (x == prev)) | (a < low_limit_checked);
      prev = x;
      if (scaled) block[u - from] = a;
    }
    if (dirty) {
      while (i < end && step(i)) ++i;
      if (i < end) break;  // this value needs screen_value
      continue;
    }
    if (stuck > 0) {
      same = 1;
      last_value = rows[(end - 1) * g + j];
    }
    if (low_check) low = 0;
    i = end;
  }
  while (i < last && step(i)) ++i;  // stuck_samples = 1 (every value completes a run)
  const std::size_t done = i - from;
  if (scaled) c.block.resize(block_start + done);
  if (done == 0) return from;
  k.screened += done;
  c.high_run = 0;
  c.last = Last::Good;
  c.same_run = same;
  c.last_value = last_value;
  c.low_run = low;
  c.healthy_run += done;
  return i;
}

bool InputScreen::at_quantisation_floor(const double* rows, std::size_t n) const {
  if (level_ != ScreenLevel::Sample || params_.stopped_max_levels == 0 || n < params_.stopped_min_rows) return false;
  const auto g = static_cast<std::size_t>(channels());
  std::vector<double> levels;
  levels.reserve(params_.stopped_max_levels + 1);
  for (std::size_t j = 0; j < g; ++j) {
    const double reference = counters_[j].reference_scale;
    const double limit = reference > 0.0 ? params_.stopped_max_ratio * reference : params_.max_abs_value;
    levels.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const double x = rows[i * g + j];
      if (!std::isfinite(x) || std::abs(x) > limit) return false;
      if (std::find(levels.begin(), levels.end(), x) != levels.end()) continue;
      levels.push_back(x);
      if (levels.size() > params_.stopped_max_levels) return false;
    }
  }
  return true;
}

void InputScreen::screen(double* rows, std::size_t n, std::vector<QualityEvent>& events) {
  const int g = channels();
  const bool floor = at_quantisation_floor(rows, n);
  if (floor || (stopped_ && n >= params_.stopped_min_rows)) {
    if (floor != stopped_) {
      stopped_ = floor;
      std::ostringstream os;
      if (floor) {
        os << "every channel at the quantisation floor (at most " << params_.stopped_max_levels
           << " distinct values, within " << params_.stopped_max_ratio
           << " x the calibration scale, over " << n << " rows): the machine is not running";
      } else {
        os << "the channels are live again: the machine is running";
      }
      emit(events, 0, floor ? QualityEventKind::MachineStopped : QualityEventKind::MachineRunning, next_index_, 1,
           os.str());
    }
  }
  if (floor) {
    // Passed unchanged and unjudged: the runs a stopped machine would leave behind start afresh.
    for (std::size_t j = 0; j < static_cast<std::size_t>(g); ++j) {
      counters_[j].screened += n;
      channels_[j].same_run = channels_[j].low_run = 0;
    }
    stopped_rows_ += n;
    next_index_ += n;
    return;
  }
  // Row by row, channel by channel, as the values arrive; a channel's common case (screen_plain_run) touches only
  // that channel's state and emits nothing, so each channel runs ahead on its own, and the values that need
  // screen_value are judged in arrival order (row, then channel): the same results and the same events in the
  // same order as one value at a time.
  const auto gu = static_cast<std::size_t>(g);
  const std::uint64_t first = next_index_;
  next_.resize(gu);
  for (std::size_t j = 0; j < gu; ++j) next_[j] = screen_plain_run(j, rows, 0, n);
  for (;;) {
    std::size_t j = gu, row = n;
    for (std::size_t u = 0; u < gu; ++u) {
      if (next_[u] < row) {
        row = next_[u];
        j = u;
      }
    }
    if (j == gu) break;
    double& x = rows[row * gu + j];
    x = screen_value(static_cast<int>(j), x, first + row, events);
    next_[j] = screen_plain_run(j, rows, row + 1, n);
  }
  next_index_ = first + n;
}

}  // namespace causal::pipeline
