#include "advice_conversions.hpp"

namespace causal::recommender {

namespace {
std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }
}  // namespace

void to_recommendation(const std::string& asset_group, const std::string& alarm_id, const AdviceItem& item,
                       causal_twin::Recommendation& out) {
  out.recommendation_id(alarm_id + "/" + std::to_string(item.rank));
  out.alarm_id(alarm_id);
  out.asset_group(asset_group);
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
}

}  // namespace causal::recommender
