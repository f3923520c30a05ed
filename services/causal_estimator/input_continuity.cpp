// causal-estimator, admission: continuity of input. After a restore from a checkpoint, input ahead of the
// checkpoint waits (held, bounded) for the source to resend the continuation; input that never arrived is counted
// where it is missed (source sequence numbers, snapshot indices), logged, and raised as the group's HEALTH alarm
// input_lost.
#include "estimator_admission.hpp"

#include <spdlog/spdlog.h>

namespace causal::estimator {

namespace {
// Inputs held per asset group while the continuation is awaited: a live source resends its backlog within a
// second of the match, so a full hold means it is not resending (the wait ends early, nothing is dropped).
constexpr std::size_t kHoldMax = 256;
}  // namespace

bool EstimatorAdmission::continues(const std::string& name, GroupState& a, bool is_continuation,
                                   const causal_twin::VibrationFrame* frame, const causal_twin::ConditionVector* condition) {
  if (!a.awaiting_continuation) return true;
  if (is_continuation) {
    a.awaiting_continuation = false;
    const std::size_t held = a.held_frames.size() + a.held_conditions.size();
    if (held > 0) {
      // The source rewound: what was held comes again after the continuation (skipped if it does not).
      a.ahead_dropped += held;
      spdlog::info("asset '{}': the source resent the continuation of the checkpoint ({} inputs ahead of it were "
                   "held and come again)", name, held);
      a.held_frames.clear();
      a.held_conditions.clear();
    }
    return true;
  }
  if (frame != nullptr) a.held_frames.push_back(*frame);
  if (condition != nullptr) a.held_conditions.push_back(*condition);
  if (std::chrono::steady_clock::now() >= a.continuation_deadline ||
      a.held_frames.size() + a.held_conditions.size() >= kHoldMax) {
    release_held(name, a);
  }
  return false;
}

void EstimatorAdmission::release_held(const std::string& name, GroupState& a) {
  a.awaiting_continuation = false;
  auto frames = std::move(a.held_frames);
  auto conditions = std::move(a.held_conditions);
  a.held_frames.clear();
  a.held_conditions.clear();
  spdlog::warn("asset '{}': the source did not resend the continuation of the checkpoint within {:.1f} s "
               "(--resume-wait): going on from the {} inputs it sent (the gap is counted as lost)",
               name, options_.resume_wait_s, frames.size() + conditions.size());
  for (const auto& f : frames) on_frame(f, nullptr);
  releasing_ = true;  // in order, straight to the filters: the gap before them is counted, not waited for
  for (const auto& c : conditions) on_condition(c, nullptr);
  releasing_ = false;
}

void EstimatorAdmission::release_expired_holds(bool all) {
  const auto now = std::chrono::steady_clock::now();
  for (auto& [name, a] : processing_.groups()) {
    if (!a.awaiting_continuation || (a.held_frames.empty() && a.held_conditions.empty())) continue;
    if (all || now >= a.continuation_deadline) release_held(name, a);
  }
}

void EstimatorAdmission::report_input_lost(const std::string& name, GroupState& a, std::uint64_t count, const char* unit,
                                      std::uint64_t first, std::uint64_t last, const std::string& detail) {
  const std::string u = unit;
  if (u == "frames") a.lost_frames += count;
  else if (u == "snapshots") a.lost_snapshots += count;
  else a.lost_conditions += count;
  if (a.lost_metric == nullptr) {
    a.lost_metric = &metrics::process_metrics().counter(
        "estimator_inputs_lost_total",
        "Inputs (frames, snapshots, condition inputs) that never reached the estimator, per asset group",
        {{"asset_group", name}});
  }
  a.lost_metric->inc(static_cast<double>(count));
  const std::string range = first == last ? fmt::format("snapshot {}", first) : fmt::format("snapshots {}..{}", first, last);
  publisher_.raise_input_alarm(name, "input_lost", causal_twin::WARNING, a.lost_alarms++, static_cast<double>(count), 0.0,
                    fmt::format("{} {} never reached the estimator ({}; {}): the twin lost this input (a restart "
                                "beyond the source's backlog, or the network), the machine did not stop",
                                count, unit, range, detail));
}

}  // namespace causal::estimator
