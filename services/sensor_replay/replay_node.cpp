#include "replay_node.hpp"

#include "replay_sources.hpp"

namespace causal::replay {

namespace {
dds::SourceDriverOptions driver_options(const ReplayOptions& o) {
  dds::SourceDriverOptions d;
  d.wait = o.wait;
  d.frames = o.source != SourceKind::FeatureTable;
  d.conditions = !d.frames;
  d.pause_when_readers_go = true;  // a restarting estimator: pause, then resend what it had not processed
  for (const auto& spec : o.wait.wait_for) d.restart_readers.push_back(dds::parse_named_readers(spec).name);
  d.write_timeout_s = 60.0;
  d.lost_is_fatal = true;  // a replay skips nothing: a write the readers do not take ends it (exit 1)
  return d;
}
}  // namespace

ReplayNode::ReplayNode(ReplayOptions options)
    : options_(std::move(options)),
      participant_(dds::to_dds_settings(options_.dds, "sensor-replay")),
      driver_(participant_, driver_options(options_)) {
  if (options_.source == SourceKind::FeatureTable) {
    source_ = std::make_unique<FeatureTableReplay>(options_);
  } else {
    source_ = std::make_unique<SnapshotReplay>(options_);
  }
}

}  // namespace causal::replay
