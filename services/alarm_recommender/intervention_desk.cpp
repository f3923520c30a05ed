#include "intervention_desk.hpp"

#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

#include <cmath>

namespace causal::recommender {

namespace {

std::string name_of(const std::map<std::string, std::vector<std::string>>& names, const std::string& group, int k) {
  const auto it = names.find(group);
  if (it != names.end() && k >= 0 && static_cast<std::size_t>(k) < it->second.size()) return it->second[static_cast<std::size_t>(k)];
  return "channel " + std::to_string(k + 1);
}

std::string outcome_text(const intervention::Outcome& o, const std::string& lever, const std::string& target) {
  using intervention::to_percent;
  const std::string what = "Intervention " + o.plan.request_id + " (" + lever + " " +
                           fmt::format("{:+.1f} %", to_percent(o.plan.delta)) + ", snapshots " +
                           std::to_string(o.plan.start) + ".." + std::to_string(o.plan.start + o.plan.duration - 1) + ")";
  if (o.status != "checked") return what + ": not checked (" + o.status + "): " + o.why + ".";
  return fmt::format("{}: {} changed {:+.1f} % against the forecast without it (snapshots {}..{}); the twin predicted "
                     "{:+.1f} % [{:+.1f}, {:+.1f}] ({:.0f} %, with the forecast's own error [{:+.1f}, {:+.1f}]): {}, "
                     "{}. Lever trust {:.2f}{}.",
                     what, target, to_percent(o.observed), o.compare_from, o.compare_to, to_percent(o.predicted),
                     to_percent(o.predicted_low), to_percent(o.predicted_high), 100.0 * o.coverage,
                     to_percent(o.check_low), to_percent(o.check_high), o.inside ? "inside" : "OUTSIDE",
                     o.improved ? "improved" : "NOT improved", o.lever_trust,
                     o.lever_claimed ? "" : ": the lever's claim is withdrawn");
}

}  // namespace

InterventionDesk::InterventionDesk(dds::Participant& participant, intervention::OutcomeCheck& check)
    : participant_(participant),
      in_(participant, dds::topics::kIntervention, dds::profiles::kInterventionReader),
      out_(participant, dds::topics::kInterventionOutcome, dds::profiles::kInterventionOutcomeWriter),
      stop_(&never_stopped_),
      check_(check),
      grants_(participant.directory(), "intervention", "approved intervention",
              "issue-identity.sh: an operator's grant names no partitions, or only those of --groups") {}

void InterventionDesk::attach(dds::EventLoop& loop) {
  stop_ = &loop.stop_flag();
  loop.attach(in_.get());
}

std::size_t InterventionDesk::take() {
  return in_.take_all([this](const causal_twin::Intervention& in, const auto& info) {
    if (!grants_.entitled(in.asset_group(), info.sample_identity.writer_guid())) {
      ++not_entitled_;
      spdlog::warn("intervention {} (approved by '{}') refused: its writer may not approve for asset group '{}' ({} "
                   "refused so far)", in.request_id(), in.approved_by(), in.asset_group(), not_entitled_);
      return;
    }
    if (in.channel() == 0 || in.target_channel() == 0 || in.duration_snapshots() == 0 ||
        !std::isfinite(in.change_percent()) || in.change_percent() <= -100.0) {
      ++invalid_;
      spdlog::warn("intervention {} refused for the outcome check: needs a lever, a target channel, a duration and a "
                   "finite change above -100 % ({} refused so far)", in.request_id(), invalid_);
      return;
    }
    intervention::InterventionPlan plan;
    plan.request_id = in.request_id();
    plan.asset_group = in.asset_group();
    plan.recommendation_id = in.recommendation_id();
    plan.lever = in.channel() - 1;
    plan.target = in.target_channel() - 1;
    plan.delta = std::log1p(in.change_percent() / 100.0);
    plan.start = in.start_snapshot_index();
    plan.duration = in.duration_snapshots();
    if (check_.approve(plan)) {
      ++approvals_;
      spdlog::info("intervention {} approved by {}: checking its outcome on channel {} after snapshots {}..{}",
                   plan.request_id, in.approved_by(), in.target_channel(), plan.start, plan.start + plan.duration - 1);
    }
  });
}

void InterventionDesk::publish_finished(const std::string& group, const std::vector<std::string>& channel_names,
                                        const std::vector<intervention::Outcome>& outcomes) {
  if (outcomes.empty()) return;
  channel_names_[group] = channel_names;
  for (const auto& o : outcomes) publish(o);
}

void InterventionDesk::publish(const intervention::Outcome& o) {
  using intervention::to_percent;
  causal_twin::InterventionOutcome m;
  m.request_id(o.plan.request_id);
  m.asset_group(o.plan.asset_group);
  m.recommendation_id(o.plan.recommendation_id);
  m.channel(static_cast<std::uint16_t>(o.plan.lever + 1));
  m.target_channel(static_cast<std::uint16_t>(o.plan.target + 1));
  m.start_snapshot_index(o.plan.start);
  m.end_snapshot_index(o.plan.start + o.plan.duration - 1);
  m.status(o.status);
  m.predicted_percent(to_percent(o.predicted));
  // The interval an observation is judged against: the twin's, widened by the forecast's own error.
  m.predicted_percent_low(to_percent(o.check_low));
  m.predicted_percent_high(to_percent(o.check_high));
  m.confidence(o.coverage);
  m.observed_percent(to_percent(o.observed));
  m.inside(o.inside);
  m.improved(o.improved);
  m.lever_trust(o.lever_trust);
  m.lever_claimed(o.lever_claimed);
  m.text(outcome_text(o, name_of(channel_names_, o.plan.asset_group, o.plan.lever),
                      name_of(channel_names_, o.plan.asset_group, o.plan.target)));
  spdlog::log(o.status == "checked" && o.inside ? spdlog::level::info : spdlog::level::warn, "INTERVENTION OUTCOME {}",
              m.text());
  if (out_.write(m, *stop_) == dds::WriteResult::Ok) {
    ++published_;
  } else {
    ++write_failures_;
    spdlog::error("intervention outcome {} not published (DDS return code {})", o.plan.request_id, out_.last_error());
  }
}

void InterventionDesk::finish() {
  take();
  const std::size_t open = check_.pending();
  if (open > 0) spdlog::warn("{} approved intervention(s) not checked: their window was not observed before the end", open);
  spdlog::info("interventions: {} approved, {} refused, {} outcomes published, {} not published, {} non-finite "
               "observations skipped by the check", approvals_, invalid_, published_, write_failures_,
               check_.rejected_non_finite());
  if (not_entitled_ > 0) {
    spdlog::error("{} approved interventions refused: their writers may not approve for their asset group ({} "
                  "writer/group pairs)", not_entitled_, grants_.refused_pairs());
  }
  spdlog::info("summary topic=causal_twin/intervention approved={} refused={} not_entitled={}", approvals_, invalid_,
               not_entitled_);
  if (!out_.wait_for_acknowledgments(std::chrono::seconds(5))) {
    spdlog::warn("not every intervention outcome was acknowledged within 5 s");
  }
}

bool InterventionDesk::lever_claimed(const std::string& group, int lever, int target, std::string& why) const {
  if (check_.trust().claimed(group, lever, target)) return true;
  const auto r = check_.trust().record_of(group, lever, target);
  why = fmt::format("its intervention outcomes fell outside the predicted interval in {} of {} checks (trust {:.2f})",
                    r.checks - r.hits, r.checks, check_.trust().trust(group, lever, target));
  return false;
}

void withdraw_if_untrusted(const InterventionDesk& desk, causal_twin::Recommendation& msg) {
  std::string why;
  if (msg.action_kind() != "upstream_lever" || msg.intervene_channel() == 0 || msg.target_channel() == 0) return;
  if (desk.lever_claimed(msg.asset_group(), msg.intervene_channel() - 1, msg.target_channel() - 1, why)) return;
  msg.reliable(false);
  msg.text(msg.text() + " Lever claim withdrawn: " + why + ".");
}

}  // namespace causal::recommender
