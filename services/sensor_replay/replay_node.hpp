// sensor-replay's DDS node: its source (replay_sources.hpp) under the one source driver (causal/dds/source_driver.hpp):
// run() publishes the whole source with pacing, stop() (from the signal thread) ends it early.
// Exit codes: 0 done, 1 bad input (or a write the readers did not take), 3 no readers.
#pragma once

#include "replay_options.hpp"

#include "causal/dds/participant.hpp"
#include "causal/dds/sample_source.hpp"
#include "causal/dds/source_driver.hpp"

#include <memory>

namespace causal::replay {

class ReplayNode {
 public:
  explicit ReplayNode(ReplayOptions options);
  int run() { return driver_.run(*source_); }
  void stop() { driver_.stop(); }

 private:
  ReplayOptions options_;
  dds::Participant participant_;
  dds::SourceDriver driver_;
  std::unique_ptr<dds::SampleSource> source_;
};

}  // namespace causal::replay
