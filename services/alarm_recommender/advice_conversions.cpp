#include "advice_conversions.hpp"

namespace causal::recommender {

namespace {
std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

// The answer's diagnostics, the same fields on a Recommendation and on a WhatIfReply.
template <class Message>
void put_diagnostics(const AnswerDiagnostics& d, Message& out) {
  out.answer_kind(d.kind);
  out.horizon_snapshots(static_cast<uint16_t>(d.horizon_snapshots));
  out.spectral_radius(d.spectral_radius);
  out.draws(static_cast<uint32_t>(d.draws));
  out.unstable_draws(static_cast<uint32_t>(d.unstable_draws));
  out.unstable_draw_share(d.unstable_share);
}
}  // namespace

void to_recommendation(const RecommendationContext& context, const AdviceItem& item, causal_twin::Recommendation& out) {
  out.recommendation_id(context.id_prefix + "/" + std::to_string(item.rank));
  out.alarm_id(context.alarm_id);
  out.asset_group(context.asset_group);
  out.rank(static_cast<uint16_t>(item.rank));
  out.target_channel(static_cast<uint16_t>(item.target + 1));
  out.intervene_channel(static_cast<uint16_t>(item.intervene + 1));
  out.delta(item.delta);
  out.effect_immediate(item.immediate);
  out.effect_steady_state(item.steady_state);
  out.effect_low(item.lower);
  out.effect_high(item.upper);
  out.confidence(item.coverage);
  out.text(item.text);
  put_diagnostics(item.diag, out);
  out.effect_median(item.effect);
  out.effect_percent(item.percent);
  out.effect_percent_low(item.percent_lower);
  out.effect_percent_high(item.percent_upper);
  out.effect_level_change(item.level_change);
  out.reliable(item.reliable);
  out.summary(item.summary);
  out.sample_index(context.sample_index);
  out.action(context.action);
  out.action_kind(context.action_kind);
  out.act_on_channel(static_cast<uint16_t>(context.act_on_channel + 1));
  out.act_on_name(context.act_on_name);
  out.horizon_hours(context.horizon_hours);
  out.order_confidence(context.order_confidence);
  out.order_source(context.order_source);
}

void to_whatif_reply(const causal_twin::WhatIfRequest& request, const WhatIfAnswer& answer, causal_twin::WhatIfReply& out) {
  out.request_id(request.request_id());
  out.asset_group(request.asset_group());
  out.ok(answer.ok);
  out.error(answer.error);
  out.effect_immediate(to_vector(answer.immediate));
  out.effect_steady_state(to_vector(answer.steady_state));
  out.effect_low(to_vector(answer.lower));
  out.effect_high(to_vector(answer.upper));
  out.text(answer.text);
  put_diagnostics(answer.diag, out);
  out.effect_median(to_vector(answer.effect));
  out.effect_percent(to_vector(answer.percent));
  out.effect_percent_low(to_vector(answer.percent_lower));
  out.effect_percent_high(to_vector(answer.percent_upper));
  out.summary(answer.summary);
  out.channel_names(answer.channel_names);
}

}  // namespace causal::recommender
