#include "block_sequencer.hpp"

#include <cmath>
#include <cstdio>

namespace causal::ingest {

namespace {
std::string ns_text(double ns) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6g s", ns * 1e-9);
  return text;
}
}  // namespace

Admission BlockSequencer::admit(const IngestBlock& block) {
  Admission a;
  FramePlan plan;
  auto it = groups_.find(block.asset_group);
  if (it == groups_.end()) {
    plan.discontinuity = true;
    plan.why = "first block of the asset group";
    it = groups_.emplace(block.asset_group, Group{}).first;
    it->second.at.channels = block.channels;
  } else {
    Group& g = it->second;
    if (block.channels != g.at.channels) {
      a.reason = RejectReason::LayoutChange;
      a.detail = "channels differ from the asset group's first block (" + std::to_string(g.at.channels.size()) +
                 " before, " + std::to_string(block.channels.size()) + " now)";
      return a;
    }
    if (g.resumed) return resumed_block(g, block, plan, a);
    // Where the previous block ended, in the source's time.
    const double period_ns = 1e9 / g.last_rate_hz;
    const double expected_t0 = static_cast<double>(g.last_t0_ns) + static_cast<double>(g.last_samples) * period_ns;
    const double late_ns = static_cast<double>(block.t0_ns) - expected_t0;  // > 0: a gap, < 0: overlap
    if (block.sequence == g.at.last_source_sequence) {
      a.reason = RejectReason::Duplicate;
      a.detail = "source sequence " + std::to_string(block.sequence) + " again";
      return a;
    }
    const bool sequence_back = block.sequence < g.at.last_source_sequence;
    if (late_ns < -0.5 * period_ns) {
      a.reason = RejectReason::OutOfOrder;
      a.detail = "block starts " + ns_text(-late_ns) + " before the previous one ended (source sequence " +
                 std::to_string(block.sequence) + " after " + std::to_string(g.at.last_source_sequence) + ")";
      return a;
    }
    if (sequence_back) {
      plan.discontinuity = true;  // time goes on: a restarted source counting from 0 again
      plan.why = "source restarted its sequence at " + std::to_string(block.sequence);
    } else if (block.sequence > g.at.last_source_sequence + 1) {
      plan.discontinuity = true;
      plan.why = "source blocks " + std::to_string(g.at.last_source_sequence + 1) + ".." +
                 std::to_string(block.sequence - 1) + " missing";
    } else if (late_ns + period_ns > gap_factor_ * period_ns) {
      plan.discontinuity = true;
      plan.why =
          "time gap of " + ns_text(late_ns + period_ns) + " between samples (sample period " + ns_text(period_ns) + ")";
    } else if (block.sample_rate_hz != g.last_rate_hz) {
      plan.discontinuity = true;
      plan.why = "sample rate changed";
    } else if (g.segment_closed) {
      plan.discontinuity = true;
      plan.why = "new segment after end_of_segment";
    }
    if (plan.discontinuity) ++g.at.snapshot_index;
  }
  return finish(it->second, block, plan, a);
}

Admission BlockSequencer::resumed_block(Group& g, const IngestBlock& block, FramePlan& plan, Admission& a) {
  // The previous run's last block time is not known here: a new segment.
  if (g.at.has_source_sequence && block.sequence == g.at.last_source_sequence) {
    a.reason = RejectReason::Duplicate;
    a.detail = "source sequence " + std::to_string(block.sequence) + " again (the last block before the restart)";
    return a;
  }
  g.resumed = false;
  plan.discontinuity = true;
  if (g.at.has_source_sequence && block.sequence > g.at.last_source_sequence + 1) {
    // Blocks lost across the restart: their numbers stay unused, so every reader sees the gap.
    plan.missed = block.sequence - g.at.last_source_sequence - 1;
    g.at.next_sequence += plan.missed;
    if (block.end_of_segment) {
      g.at.snapshot_index += plan.missed;
      g.at.next_sample_index += plan.missed * block.samples_per_channel;
    }
  }
  plan.why = "first block after sensor-ingest restarted: numbering resumed at frame " +
             std::to_string(g.at.next_sequence) + ", sample " + std::to_string(g.at.next_sample_index) +
             (plan.missed > 0 ? " (source blocks " + std::to_string(g.at.last_source_sequence + 1) + ".." +
                                    std::to_string(block.sequence - 1) + " never reached sensor-ingest: lost)"
                              : std::string());
  ++g.at.snapshot_index;
  return finish(g, block, plan, a);
}

Admission BlockSequencer::finish(Group& g, const IngestBlock& block, FramePlan& plan, Admission& a) {
  plan.sequence = g.at.next_sequence++;
  plan.first_sample_index = g.at.next_sample_index;
  plan.snapshot_index = g.at.snapshot_index;
  g.at.next_sample_index += block.samples_per_channel;
  g.at.last_source_sequence = block.sequence;
  g.at.has_source_sequence = true;
  g.last_t0_ns = block.t0_ns;
  g.last_samples = block.samples_per_channel;
  g.last_rate_hz = block.sample_rate_hz;
  g.segment_closed = block.end_of_segment;
  a.plan = plan;
  return a;
}

void BlockSequencer::resume(const std::string& group, const ResumePoint& point) {
  Group g;
  g.at = point;
  g.resumed = true;
  groups_[group] = std::move(g);
}

std::optional<ResumePoint> BlockSequencer::resume_point(const std::string& group) const {
  const auto it = groups_.find(group);
  if (it == groups_.end()) return std::nullopt;
  return it->second.at;
}

}  // namespace causal::ingest
