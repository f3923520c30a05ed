#include "recommendation_store.hpp"

namespace causal::recommender {

bool restore_decision(const causal_twin::Alarm& kept, causal_twin::Alarm& rebuilt) {
  if (kept.alarm_id() != rebuilt.alarm_id() || kept.state() != rebuilt.state() ||
      kept.severity() != rebuilt.severity() || kept.sample_index() != rebuilt.sample_index()) {
    return false;
  }
  rebuilt.action(kept.action());
  rebuilt.next_level(kept.next_level());
  rebuilt.hours_to_next_level(kept.hours_to_next_level());
  rebuilt.hours_to_next_level_low(kept.hours_to_next_level_low());
  rebuilt.hours_to_next_level_high(kept.hours_to_next_level_high());
  return true;
}

}  // namespace causal::recommender
