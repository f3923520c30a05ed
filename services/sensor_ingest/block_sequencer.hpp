// Turns the source's blocks of one or more asset groups into the frame stream the IDL asks for, DDS-free:
// per asset group, frame sequence numbers 0, 1, 2, ... with no gaps (a gap on the topic means frames lost
// between the adapter and the reader, so the adapter never creates one) and first_sample_index counting
// every sample published. What the source skipped is not a lost frame: a gap in the source's sequence or
// time, a changed sample rate, a restarted source or a new segment after end_of_segment is flagged with
// VibrationFrame.discontinuity (as sensor-replay flags each new snapshot), so the estimator restarts its
// lags there, and opens a new snapshot index (the condition-level index of the segment).
//
// Time gap rule: the interval from the previous block's last sample to this block's first sample is a
// gap when it exceeds gap_factor x the sample period (1.5: at least one sample is missing, while clock
// jitter under half a sample is not).
// Restarts: a live source cannot resend what it published before, so a restarted sensor-ingest must not number
// from 0 again (the estimator would take its frames for ones it already processed). resume() gives a group the
// numbering a previous run left (ingest_state_store.hpp); its first block then continues it: sequence and sample
// index go on, the snapshot index advances and the frame is a discontinuity ("sensor-ingest restarted").
// Blocks lost across the restart: when the source's sequence goes on past the last block the previous run took
// (ResumePoint::last_source_sequence), the blocks between never reached sensor-ingest (inside the killed process,
// or sent while it was down by a source that does not queue: stdin, UDP). They are not a pause of the source: the
// frame sequence skips one number per missing block, so the estimator counts them as lost frames (HEALTH
// input_lost), and with per-block segments (end_of_segment) the snapshot index and the sample index skip them too,
// so the recorder's gap and the alarm engine's input_lost name the same snapshots (FramePlan::missed).
// Rejected (not published, counted): channels other than the group's first block had (layout_change), a
// source sequence number seen already (duplicate: MQTT QoS 1 may deliver twice), and a block that starts
// before the previous one ended (out_of_order: time going backwards or overlapping).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ingest_block.hpp"

namespace causal::ingest {

// What the frame for an admitted block carries besides the samples.
struct FramePlan {
  std::uint64_t sequence = 0;            // frame sequence number, per asset group, gap-free
  std::uint64_t first_sample_index = 0;  // samples published for this group before this frame
  std::uint64_t snapshot_index = 0;      // segment counter: +1 at every discontinuity after the first
  bool discontinuity = false;
  std::string why;  // why a discontinuity ("" when none), for the log
  std::uint64_t missed = 0;  // source blocks that never reached sensor-ingest across its restart (counted lost)
};

struct Admission {
  std::optional<FramePlan> plan;  // set when admitted
  RejectReason reason = RejectReason::OutOfOrder;
  std::string detail;
};

// Where a group's numbering stands: what the next admitted block would get (saved after every block).
struct ResumePoint {
  std::vector<std::string> channels;
  std::uint64_t next_sequence = 0;
  std::uint64_t next_sample_index = 0;
  std::uint64_t snapshot_index = 0;  // of the last frame published
  bool has_source_sequence = false;  // the source's sequence of the last block taken (state written since v2)
  std::uint64_t last_source_sequence = 0;
};

class BlockSequencer {
 public:
  explicit BlockSequencer(double gap_factor = 1.5) : gap_factor_(gap_factor) {}
  // Decides about one parsed block and, when it is admitted, advances the group's state.
  Admission admit(const IngestBlock& block);
  std::size_t groups() const { return groups_.size(); }
  bool knows(const std::string& group) const { return groups_.count(group) > 0; }
  // Continues a group's numbering from a previous run (call before the group's first block).
  void resume(const std::string& group, const ResumePoint& point);
  // The group's numbering now (nullopt for an unknown group).
  std::optional<ResumePoint> resume_point(const std::string& group) const;

 private:
  struct Group {
    // The numbering (what resume() restores and resume_point() saves); at.has_source_sequence: the source's
    // sequence of the last block is known (a block taken, or restored).
    ResumePoint at;
    std::int64_t last_t0_ns = 0;
    std::size_t last_samples = 0;
    double last_rate_hz = 0.0;
    bool segment_closed = false;  // the last block had end_of_segment
    bool resumed = false;         // numbering restored from a previous run, no block of this run yet
  };
  Admission finish(Group& g, const IngestBlock& block, FramePlan& plan, Admission& a);
  // The first block after a restart (resume()): a new segment; blocks the source sent meanwhile and this process
  // never took are skipped in the numbering (FramePlan::missed).
  Admission resumed_block(Group& g, const IngestBlock& block, FramePlan& plan, Admission& a);
  double gap_factor_;
  std::map<std::string, Group> groups_;
};

}  // namespace causal::ingest
