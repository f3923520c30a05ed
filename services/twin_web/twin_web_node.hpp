// twin-web's DDS node: reads condition vectors, causal factors, alarms, recommendations and what-if replies
// into TwinState / WhatIfBridge on the service's run-loop thread, and writes the what-if requests the page
// asks. The web server (its own threads) only sees the state's serialised copy and the bridge.
#pragma once

#include "approval_keeper.hpp"
#include "history_interventions.hpp"
#include "history_loader.hpp"
#include "history_routes.hpp"
#include "twin_state.hpp"
#include "web_server.hpp"
#include "whatif_bridge.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/service_runtime.hpp"
#include "causal/dds/twin_output_readers.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/metrics/metrics_registry.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <memory>

namespace causal::web {

struct TwinWebOptions {
  dds::CommonOptions dds;
  WebOptions web;
  StateLimits limits;
  double idle_exit_s = 0.0;    // exit this long after every publisher left, once data came (0 = never)
  double max_runtime_s = 0.0;  // hard stop (0 = none)
  std::string db_url;          // --db: the historian's database, drawn at start and served for older ranges
};

class TwinWebNode {
 public:
  explicit TwinWebNode(TwinWebOptions options);  // throws std::runtime_error (DDS, port in use)
  ~TwinWebNode();
  int run();
  void stop() { loop_.stop(); }

 private:
  std::size_t take_available();
  void load_history_at_start();
  void send_due_questions();
  void send_due_actions();

  TwinWebOptions options_;
  TwinState state_;
  metrics::Gauge* missing_metric_ = &metrics::process_metrics().gauge(
      "web_snapshots_missing", "Snapshot indices missing in the live view's trends (skipped: input lost upstream)");
  WhatIfBridge whatif_;
  std::atomic<std::size_t> whatif_readers_{0};
  dds::Participant participant_;
  dds::TwinOutputReaders in_;
  dds::TypedReader<causal_twin::WhatIfReplyPubSubType> replies_in_;
  dds::TypedWriter<causal_twin::WhatIfRequestPubSubType> requests_out_;
  AlarmActionBridge actions_;  // the page's acknowledge / shelve, out on causal_twin/alarm_action
  dds::TypedWriter<causal_twin::AlarmActionPubSubType> actions_out_;
  // The closed loop: approvals (the approve button, causal-approve) and the twin's checks of them
  // (alarm-recommender); the approvals are kept on twin-web's durable writer (approval_keeper.hpp).
  dds::TypedReader<causal_twin::InterventionPubSubType> interventions_in_;
  dds::TypedReader<causal_twin::InterventionOutcomePubSubType> intervention_outcomes_in_;
  ApprovalKeeper approvals_;
  // The plant's clock for the approve button: the source's condition inputs (volatile: what comes from now on).
  dds::TypedReader<causal_twin::ConditionVectorPubSubType> inputs_in_;
  SourceClock source_clock_;
  std::uint64_t actions_sent_ = 0, actions_failed_ = 0;
  dds::FactorSetCounts factor_set_counts_;  // causal_twin/causal_factor_sets, unpacked into state_
  dds::EventLoop loop_;  // after the readers: detaches their conditions first
  std::unique_ptr<history::HistoryStore> history_;
  std::unique_ptr<HistoryRoutes> history_routes_;
  HistoryLoad loaded_;  // what came from the database at start (not counted as received from DDS)
  InterventionLoad loaded_interventions_;
  std::unique_ptr<WebServer> web_;
  std::uint64_t requests_sent_ = 0, requests_failed_ = 0, replies_received_ = 0;
};

}  // namespace causal::web
