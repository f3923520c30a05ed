// alarm-recommender --wait-for: before it takes input, the named readers (the recorder, a historian) are matched on
// every output topic, as causal-estimator --wait-for does for its factor readers. The writers keep the last 64
// changes per key for late joiners; the asset status changes at every snapshot while a group learns, so a recorder
// that matched after that ring turned over recorded a shorter history (CI: 396 of 428 status rows, exit 0).
// And the other end: "caught up" once the sources left and all they sent is judged and acknowledged (note_caught_up).
#include "recommender_node.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

#include <functional>
#include <string>
#include <vector>

namespace causal::recommender {

int RecommenderNode::wait_for_readers() {
  if (options_.wait_for.empty()) return config::kExitOk;
  // Input that arrives meanwhile waits in the reliable readers (the estimator blocks on them): nothing is lost.
  std::vector<dds::NamedReaders> wanted;
  for (const auto& spec : options_.wait_for) wanted.push_back(dds::parse_named_readers(spec));
  const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.wait_timeout_s * 1000.0));
  const auto& stop = loop_.stop_flag();
  struct Output {
    const char* topic;
    std::function<std::string()> wait;
  };
  const Output outputs[] = {
      {dds::topics::kAlarm, [&] { return dds::wait_for_named_readers(alarms_, wanted, timeout, stop); }},
      {dds::topics::kRecommendation, [&] { return dds::wait_for_named_readers(recommendations_, wanted, timeout, stop); }},
      {dds::topics::kAssetStatus, [&] { return dds::wait_for_named_readers(status_writer_, wanted, timeout, stop); }},
      {dds::topics::kPrognosis, [&] { return dds::wait_for_named_readers(prognoses_, wanted, timeout, stop); }},
  };
  for (const auto& out : outputs) {
    const std::string missing = out.wait();
    if (missing.empty()) continue;
    if (loop_.stopped()) return config::kExitOk;
    spdlog::error("no '{}' reader of {} matched within {:.0f} s: is it running on domain {} with the same transport "
                  "profile?", missing, out.topic, options_.wait_timeout_s, participant_.domain_id());
    return config::kExitNoPeer;
  }
  std::string names;
  for (const auto& spec : options_.wait_for) names += (names.empty() ? "" : ", ") + spec;
  spdlog::info("readers matched on every output topic: {}", names);
  return config::kExitOk;
}

void RecommenderNode::note_caught_up(bool sources_gone, std::size_t taken) {
  if (!sources_gone) {
    sources_seen_ = true;
    caught_up_logged_ = false;
    return;
  }
  if (!sources_seen_ || caught_up_logged_ || taken > 0) return;
  // Reliable writers: acknowledged means every matched reader holds what was published (a kill -9 from now on
  // loses nothing a live reader would have seen). Not yet: asked again at the next poll, never waited for here.
  const std::chrono::milliseconds at_once{0};
  if (!alarms_.wait_for_acknowledgments(at_once) || !recommendations_.wait_for_acknowledgments(at_once) ||
      !prognoses_.wait_for_acknowledgments(at_once) || !status_writer_.wait_for_acknowledgments(at_once)) {
    return;
  }
  caught_up_logged_ = true;
  spdlog::info("caught up: every source of causal factors and condition vectors left, the {} observations taken are "
               "judged, and every reader acknowledged the alarms, recommendations, prognoses and statuses published",
               observations_judged_);
}

}  // namespace causal::recommender
