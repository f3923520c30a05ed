// causal-estimator: the node wires its three roles (admission, processing, publishing) to one participant and one
// event loop, runs the loop and, at the end, finishes each role in turn.
#include "estimator_node.hpp"

#include "causal/config/exit_codes.hpp"

#include <spdlog/spdlog.h>

namespace causal::estimator {

namespace {
// The participant announces its shard (the asset-group filter expression, "" unsharded): a hot standby follows
// only the primary of its own shard, so another shard's estimator is never taken for its primary.
dds::DdsSettings estimator_dds_settings(const EstimatorOptions& options) {
  auto settings = dds::to_dds_settings(options.dds, "causal-estimator");
  settings.role_tag = shard_role_tag(options.groups);
  return settings;
}
}  // namespace

// admission_ is constructed before publisher_ and processing_ (it creates the readers first) and only keeps
// references to them until its first take().
EstimatorNode::EstimatorNode(EstimatorOptions options, pipeline::AssetPipelineParams params)
    : options_(std::move(options)),
      participant_(estimator_dds_settings(options_)),
      trace_(options_.stage_trace),
      admission_(participant_, options_, processing_, publisher_, trace_),
      publisher_(participant_, options_, params.condition_model.fixed_lag, loop_.stop_flag()),
      processing_(options_, std::move(params), publisher_) {
  admission_.attach(loop_);
}

int EstimatorNode::run() {
  if (options_.groups.all()) {
    spdlog::info("causal-estimator on domain {}, every asset group, waiting for frames", participant_.domain_id());
  } else {
    spdlog::info("causal-estimator on domain {}, shard {}: {} (content filter '{}' on frames and condition inputs, "
                 "evaluated by the sources' writers), waiting for frames",
                 participant_.domain_id(), options_.shard_name, options_.groups.describe(), options_.groups.expression());
  }
  if (!options_.wait_for.empty()) {
    // Input that arrives meanwhile waits in the reliable, transient-local readers: nothing is lost.
    std::vector<dds::NamedReaders> wanted;
    for (const auto& spec : options_.wait_for) wanted.push_back(dds::parse_named_readers(spec));
    const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.wait_timeout_s * 1000.0));
    const std::string missing = publisher_.wait_for_readers(wanted, timeout);
    if (!missing.empty()) {
      if (loop_.stopped()) return config::kExitOk;
      spdlog::error("no '{}' reader of causal factors matched within {:.0f} s: is it running on domain {} with the "
                    "same transport profile?",
                    missing, options_.wait_timeout_s, participant_.domain_id());
      return config::kExitNoPeer;
    }
  }
  dds::RunLimits limits;
  limits.idle_exit_s = options_.idle_exit_s;
  limits.max_runtime_s = options_.max_runtime_s;
  // A shard may own none of the groups a source publishes and then receives nothing at all: for it, sources
  // that came and left are the end of the run (otherwise it would never be idle, and never exit).
  if (!options_.groups.all()) limits.sources_came = [this] { return admission_.matched_writers_total() > 0; };
  publisher_.start();
  const auto end = loop_.run(
      limits,
      [this] {
        publisher_.watch_primary();
        const std::size_t n = admission_.take(loop_.stop_flag());
        admission_.tick();
        publisher_.publish_health(admission_.health());
        return n;
      },
      // Idle exit only once every source has left: a source that is merely blocked or paced must not end the run.
      [this] { return admission_.matched_writers(); });
  if (end == dds::RunEnd::Idle) spdlog::info("all sources gone and no data for {:.1f} s: finishing", options_.idle_exit_s);
  if (end == dds::RunEnd::MaxRuntime) spdlog::warn("max runtime {:.0f} s reached: finishing", options_.max_runtime_s);
  return finish_all();
}

int EstimatorNode::finish_all() {
  admission_.finish();
  processing_.finish();
  publisher_.finish(loop_.stopped());
  return log_summary();
}

}  // namespace causal::estimator
