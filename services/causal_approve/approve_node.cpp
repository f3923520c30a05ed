#include "approve_node.hpp"

#include "causal/dds/topics.hpp"
#include "causal/io/time_format.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace causal::approve {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

ApproveNode::ApproveNode(ApproveOptions options)
    : options_(std::move(options)),
      participant_(dds::to_dds_settings(options_.dds, "causal-approve")),
      recommendations_(participant_, dds::topics::kRecommendation, dds::profiles::kRecommendationReader),
      conditions_(participant_, dds::topics::kConditionVector, dds::profiles::kConditionVectorReader),
      inputs_(participant_, dds::topics::kConditionInput, dds::profiles::kConditionInputReader),
      interventions_(participant_, dds::topics::kIntervention, dds::profiles::kInterventionWriter) {
  if (options_.asset_group.empty()) throw std::invalid_argument("--group must not be empty");
  if (options_.recommendation_id.empty()) throw std::invalid_argument("--recommendation must not be empty");
  if (options_.user.empty()) throw std::invalid_argument("--user must not be empty");
  if (options_.duration && *options_.duration == 0) throw std::invalid_argument("--duration must be at least 1");
  loop_.attach(recommendations_.get());
  loop_.attach(conditions_.get());
  loop_.attach(inputs_.get());
}

std::optional<causal_twin::Recommendation> ApproveNode::find_recommendation(Clock::time_point deadline) {
  std::optional<causal_twin::Recommendation> found;
  std::optional<Clock::time_point> found_at;
  while (!loop_.stopped() && Clock::now() < deadline) {
    recommendations_.take_all([&](const causal_twin::Recommendation& r, const auto&) {
      if (r.recommendation_id() == options_.recommendation_id) found = r;  // the latest value of that id
    });
    const auto latest = [&](const causal_twin::ConditionVector& c, bool input) {
      if (c.asset_group() != options_.asset_group) return;
      input_seen_ = input_seen_ || input;
      if (latest_index_ && c.snapshot_index() <= *latest_index_) return;
      if (latest_index_ && c.snapshot_index() == *latest_index_ + 1) cadence_ns_ = c.time_ns() - latest_time_ns_;
      latest_index_ = c.snapshot_index();
      latest_time_ns_ = c.time_ns();
    };
    conditions_.take_all([&](const causal_twin::ConditionVector& c, const auto&) { latest(c, false); });
    inputs_.take_all([&](const causal_twin::ConditionVector& c, const auto&) { latest(c, true); });
    if (found && (input_seen_ || options_.start_index)) return found;
    // The source may publish frames, or nothing more (a recommender fed elsewhere): after 3 s the estimator's latest
    // condition vector (or the recommendation's own index) is the best known.
    if (found && !found_at) found_at = Clock::now();
    if (found_at && Clock::now() - *found_at > std::chrono::seconds(3)) return found;
    (void)loop_.wait(std::chrono::milliseconds(100));
  }
  return found;
}

bool ApproveNode::readers_ready(Clock::time_point deadline) {
  while (!loop_.stopped() && Clock::now() < deadline) {
    bool ok = interventions_.matched_readers() > 0;
    for (const auto& name : options_.wait_for) ok = ok && interventions_.matched_readers_named(name) > 0;
    if (ok) return true;
    (void)loop_.wait(std::chrono::milliseconds(50));
  }
  return false;
}

int ApproveNode::run() {
  const auto deadline = Clock::now() + std::chrono::milliseconds(static_cast<long>(options_.timeout_s * 1000.0));
  const auto rec = find_recommendation(deadline);
  if (!rec) {
    if (!loop_.stopped()) {
      spdlog::error("recommendation '{}' not found on domain {} within {:.0f} s (is alarm-recommender running?)",
                    options_.recommendation_id, participant_.domain_id(), options_.timeout_s);
    }
    return kNotDelivered;
  }
  std::uint64_t start = rec->sample_index() + options_.lead;
  if (latest_index_) start = *latest_index_ + options_.lead;
  if (options_.start_index) start = *options_.start_index;
  const std::int64_t start_time_ns = dds::start_time_of(start, latest_index_, latest_time_ns_, cadence_ns_);
  const std::int64_t now_ns = io::utc_now_ns();
  dds::Approval a = dds::make_approval(*rec, {options_.asset_group, options_.user, options_.duration}, start, start_time_ns, now_ns);
  if (!a.why.empty()) {
    spdlog::error("not approved: {}", a.why);
    return kNotApprovable;
  }
  if (!readers_ready(deadline)) {
    spdlog::error("no reader of {} matched within {:.0f} s{}: nothing would apply the intervention; not published",
                  dds::topics::kIntervention, options_.timeout_s,
                  options_.wait_for.empty() ? "" : " (waited for the named participants too)");
    return kNotDelivered;
  }
  const auto& iv = a.intervention;
  if (interventions_.write(a.intervention, loop_.stop_flag(), std::chrono::seconds(5)) != dds::WriteResult::Ok) {
    spdlog::error("intervention {} not published (DDS return code {})", iv.request_id(), interventions_.last_error());
    return kNotDelivered;
  }
  // The approval is delivered once every matched reader (the plant's actuator, the recommender, the recorder)
  // has acknowledged it: the tool stays until then (bounded), since its transient-local copy leaves with it.
  const auto left = std::max(std::chrono::milliseconds(1000),
                             std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()));
  const bool acknowledged = interventions_.wait_for_acknowledgments(left);
  std::printf("approved %s: %s channel %u level %+.1f %% for %u snapshots from snapshot %llu (answers %s, by %s); "
              "readers=%zu acknowledged=%s\n",
              iv.request_id().c_str(), iv.asset_group().c_str(), iv.channel(), iv.change_percent(),
              iv.duration_snapshots(), static_cast<unsigned long long>(iv.start_snapshot_index()),
              iv.recommendation_id().c_str(), iv.approved_by().c_str(), interventions_.matched_readers(),
              acknowledged ? "yes" : "no");
  std::fflush(stdout);
  return acknowledged ? kPublished : kNotDelivered;
}

}  // namespace causal::approve
