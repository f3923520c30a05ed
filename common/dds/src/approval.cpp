#include "causal/dds/approval.hpp"

#include <algorithm>
#include <cmath>

namespace causal::dds {

Approval make_approval(const causal_twin::Recommendation& rec, const ApprovalAct& act, std::uint64_t start,
                       std::int64_t start_time_ns, std::int64_t now_ns) {
  Approval a;
  if (rec.asset_group() != act.asset_group) {
    a.why = "recommendation " + rec.recommendation_id() + " is for asset group '" + rec.asset_group() + "', not '" +
            act.asset_group + "'";
  } else if (rec.action_kind() != "upstream_lever" || !rec.reliable()) {
    a.why = "recommendation " + rec.recommendation_id() + " claims no reliable lever (action kind '" +
            rec.action_kind() + "'): there is no level change to apply; act on the asset as its action says";
  } else if (!std::isfinite(rec.delta()) || rec.intervene_channel() == 0) {
    a.why = "recommendation " + rec.recommendation_id() + " has no finite intervention";
  } else if (act.user.empty()) {
    a.why = "an approval needs the name of who approves it";
  }
  if (!a.why.empty()) return a;
  auto& iv = a.intervention;
  iv.asset_group(rec.asset_group());
  iv.channel(rec.intervene_channel());
  // The recommendation's delta is in the model's units, the log level (log_transform): a level change of
  // 100 (e^delta - 1) percent.
  iv.change_percent(100.0 * std::expm1(rec.delta()));
  iv.start_snapshot_index(start);
  iv.start_time_ns(start_time_ns);
  iv.duration_snapshots(static_cast<std::uint32_t>(
      act.duration.value_or(std::max<std::uint64_t>(12, rec.horizon_snapshots()))));
  iv.recommendation_id(rec.recommendation_id());
  iv.target_channel(rec.target_channel());
  iv.approved_by(act.user);
  iv.approved_time_ns(now_ns);
  // Chosen here, the same for the same approval: who, which advice, from which snapshot.
  iv.request_id(act.asset_group + "/" + rec.recommendation_id() + "@" + std::to_string(start) + "/" + act.user);
  return a;
}

std::int64_t start_time_of(std::uint64_t start, std::optional<std::uint64_t> latest_index, std::int64_t latest_time_ns,
                           std::int64_t cadence_ns) {
  if (!latest_index || cadence_ns <= 0 || start < *latest_index) return 0;
  return latest_time_ns + static_cast<std::int64_t>(start - *latest_index) * cadence_ns;
}

}  // namespace causal::dds
