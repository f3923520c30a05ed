// Per-channel input screen of one asset group: bad values and broken channels are turned into NaN (which the
// filter rejects and counts) BEFORE any estimator sees them, and every decision is reported as an event.
//
// Per value, in this order:
//  * non-finite (NaN, +-inf)                    -> NaN, counted (non_finite);
//  * |x| > max_abs_value (not a physical reading) -> NaN, counted (out_of_range);
//  * |x| > scale_explosion x the channel's reference scale (see below) -> NaN, counted (out_of_range); a run of
//    sudden_run of them in a row quarantines the channel (scale_change) without waiting for the block verdict;
//  * otherwise the value is a measurement and feeds the channel's health checks:
//      - stuck: the exact same value stuck_samples times in a row (a dead or frozen channel, e.g. all zeros);
//      - scale change: the robust magnitude (median |x|) of each block of scale_window values compared with the
//        channel's own reference, the median |x| of its first block with a non-zero median (its calibration);
//        below scale_collapse or above scale_explosion times the reference is a gain / unit / wiring fault.
//      - sudden collapse: sudden_run values in a row below scale_collapse x reference (stuck if they are all
//        equal, e.g. a dead channel reading 0; scale_change otherwise);
//    Any of these QUARANTINES the channel: its values become NaN (counted, quarantined_values) until it has shown
//    recovery_samples consecutive values with no stuck run and no out-of-range block, then it recovers.
// A stopped machine is an operating state, not a fault: a raw frame (>= stopped_min_rows rows)
// in which EVERY channel takes at most stopped_max_levels distinct values, all within stopped_max_ratio x the
// channel's calibration scale (once known), is the ADC's quantisation floor (IMS test 2's last snapshot: values
// -0.005, -0.002, 0, +0.002 on all four bearings). Such frames pass unchanged and unjudged (no stuck, scale or
// collapse evidence: a stopped machine is not a dead channel), counted as stopped_rows; the screen reports
// MachineStopped when it enters that state and MachineRunning when a frame is live again. One dead channel reading
// 0 while the others run is still a stuck channel; a disconnected sensor (noise x1e-9) has many levels and is
// still a scale change. Frames shorter than stopped_min_rows are screened value by value as before.
// Events: one per run of non-finite or out-of-range values (at the run's first value), one when a channel
// enters quarantine (with the cause that triggered it; a second cause while quarantined only delays recovery),
// one when it recovers. Detection delays are inherent: a stuck run passes its first stuck_samples - 1 values,
// a scale change passes up to one block before the verdict.
//
// Only Eigen and the standard library; nothing here throws because of data (invalid PARAMETERS throw at
// construction).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace causal::pipeline {

enum class ScreenLevel { Sample, Condition };  // raw frame rows / ready-made condition vectors
enum class QualityEventKind { NonFinite, OutOfRange, Stuck, ScaleChange, Recovered, MachineStopped, MachineRunning };
const char* to_string(ScreenLevel level);       // "sample", "condition"
// "non_finite", "out_of_range", "stuck", "scale_change", "recovered", "machine_stopped", "machine_running"
const char* to_string(QualityEventKind kind);

// Thresholds. Defaults for raw vibration (g or V at ~20 kHz): for_samples(); for per-snapshot condition
// features (one vector per snapshot, e.g. every 10 min): for_conditions(). 0 disables a count-based check.
struct InputScreenParams {
  // Physical limit of the sensor chain: industrial accelerometers saturate between 50 and 500 g (and +-10 V
  // at the ADC), so 1e6 is far above any real reading and only catches corrupted values (1e300, garbage bits).
  double max_abs_value = 1e6;
  // Exact repeats that make a channel stuck. A live channel's ADC noise changes the value almost every sample;
  // even a quiet channel quantised to a few levels repeats a value at most a handful of times in a row.
  std::size_t stuck_samples = 256;
  // Values per block of the robust scale check (median |x| per block).
  std::size_t scale_window = 1024;
  // Allowed ratio of a block's median |x| to the channel's reference. x1000 (60 dB) either way: a bearing on
  // its way to failure raises vibration by x10 to x100 at most, a machine coasting down stays within x100 of
  // its running level above the sensor's noise floor; x1000 and beyond is a unit mix-up (mV read as V),
  // a broken gain stage, a disconnected sensor (x1e-9) or an overflowing one (x1e6).
  double scale_collapse = 1e-3;
  double scale_explosion = 1e3;
  // Once the reference is known a single value above scale_explosion x reference (about 700 standard
  // deviations of the healthy signal; real impacts stay within a few tens) is out of range too. sudden_run
  // such values in a row, or sudden_run values in a row below scale_collapse x reference, quarantine the channel
  // at once: a broken channel must not leak a whole block into the filter while its block median is collected.
  // A live channel crosses zero, so single small values are normal, but even a channel whose noise spans only
  // a few ADC steps is below 1/1000 of its median magnitude with probability < 0.5 per value: 32 in a row
  // (< 1e-9) does not happen by chance.
  std::size_t sudden_run = 32;
  // Consecutive healthy values (no stuck run, no out-of-range block) before a quarantined channel is used
  // again; >= scale_window so at least one whole block must be back in range.
  std::size_t recovery_samples = 4096;
  // Stopped machine (see above). 8 levels: a 12-bit ADC at rest shows 3-5 (IMS: 4); a running machine's 1024
  // samples take hundreds. A quarter of the calibration scale: the floor is far below the running level (IMS:
  // |x| <= 0.005 against a median |x| of about 0.06), a channel stuck at its rail is not. 0 disables.
  std::size_t stopped_max_levels = 8;
  double stopped_max_ratio = 0.25;
  std::size_t stopped_min_rows = 64;

  static InputScreenParams for_samples() { return {}; }
  // Condition features are computed over whole snapshots (20480 noisy samples): they never repeat exactly,
  // so 10 identical vectors in a row (100 min at IMS cadence) is a frozen source; blocks of 10 vectors give a
  // stable median; recovery after 30 healthy vectors (3 blocks).
  static InputScreenParams for_conditions() {
    InputScreenParams p;
    p.stuck_samples = 10;
    p.scale_window = 10;
    p.recovery_samples = 30;
    p.stopped_max_levels = 0;  // one vector per snapshot: the recommender's operating-state gate judges levels
    return p;
  }
};

struct QualityEvent {
  ScreenLevel level = ScreenLevel::Sample;
  int channel = 0;                 // 0-based
  QualityEventKind kind = QualityEventKind::NonFinite;
  std::uint64_t index = 0;         // the value's sample index (sample level) or condition vector index
  std::uint64_t count = 0;         // cumulative count of this kind on this channel, this event included
  std::string reason;              // human-readable, 1-based channel
};

struct ChannelQualityCounters {
  std::uint64_t screened = 0;            // values seen
  std::uint64_t non_finite = 0;          // replaced by NaN: NaN or inf
  std::uint64_t out_of_range = 0;        // replaced by NaN: |x| > max_abs_value
  std::uint64_t quarantined_values = 0;  // replaced by NaN: the channel was quarantined
  std::uint64_t stuck = 0;               // quarantines caused by a stuck run
  std::uint64_t scale_change = 0;        // quarantines caused by a scale change
  std::uint64_t recovered = 0;           // recoveries
  bool quarantined = false;              // now
  double reference_scale = 0.0;          // median |x| of the calibration block (0: not yet known)
};

class InputScreen {
 public:
  // Throws std::invalid_argument for invalid parameters (channels < 1, max_abs_value not > 0, ratios not
  // 0 < collapse < 1 < explosion, recovery_samples < scale_window).
  InputScreen(InputScreenParams params, int channels, ScreenLevel level);

  // Screens n rows of G values (sample-major, rows[i * G + j]) in place; events are appended to `events`.
  void screen(double* rows, std::size_t n, std::vector<QualityEvent>& events);
  // The source's index of the next row screened (sample index / condition vector index): events name the data by
  // the source's indices, also after a restart from a checkpoint (the screen itself starts afresh) or a gap.
  void continue_at(std::uint64_t index) { next_index_ = index; }

  int channels() const { return static_cast<int>(channels_.size()); }
  bool machine_stopped() const { return stopped_; }
  std::uint64_t stopped_rows() const { return stopped_rows_; }
  const std::vector<ChannelQualityCounters>& counters() const { return counters_; }
  const InputScreenParams& params() const { return params_; }

 private:
  enum class Last { Good, NonFinite, OutOfRange };
  struct ChannelState {
    Last last = Last::Good;
    double last_value = 0.0;
    std::size_t same_run = 0;       // length of the current run of identical values
    std::size_t healthy_run = 0;    // consecutive values without stuck / scale evidence
    std::size_t high_run = 0;       // consecutive values above scale_explosion x reference
    std::size_t low_run = 0;        // consecutive values below scale_collapse x reference
    std::vector<double> block;      // |x| of the current scale block
    // scale_verdict_by_counting's exact bounds for bounds_reference: |x| / reference < collapse exactly when
    // |x| < collapse_below, > explosion exactly when |x| > explosion_above.
    double bounds_reference = 0.0, collapse_below = 0.0, explosion_above = 0.0;
  };
  double screen_value(int j, double x, std::uint64_t index, std::vector<QualityEvent>& events);
  std::size_t screen_plain_run(std::size_t j, const double* rows, std::size_t from, std::size_t n);
  double screen_exploded(int j, ChannelState& c, ChannelQualityCounters& k, double x, std::uint64_t index,
                         std::vector<QualityEvent>& events);
  bool scale_block_bad(int j, ChannelState& c);
  bool at_quantisation_floor(const double* rows, std::size_t n) const;
  int scale_verdict_by_counting(ChannelState& c, double reference) const;
  void emit(std::vector<QualityEvent>& events, int j, QualityEventKind kind, std::uint64_t index,
            std::uint64_t count, std::string reason) const;

  InputScreenParams params_;
  ScreenLevel level_;
  std::vector<ChannelState> channels_;
  std::vector<ChannelQualityCounters> counters_;
  std::uint64_t next_index_ = 0;
  bool stopped_ = false;
  std::uint64_t stopped_rows_ = 0;
  std::vector<std::size_t> next_;  // screen(): per channel, the next row its common case did not take
};

}  // namespace causal::pipeline
