// sensor-sim's condition-level plant mode (--plant): simulated plants (level_plant.hpp) publish one condition
// vector per group and snapshot on causal_twin/condition_input, and obey approved interventions read from
// causal_twin/intervention: each is applied to its group's true structural model as the do-operation (P2) from
// its start snapshot index, so the data depend on the approvals and their indices only (same input, same output).
// An intervention for another group is not ours (counted, ignored); one that cannot be applied as approved
// (its start already published, a bad channel or size, an overlap) is refused, logged and counted (exit 4), and
// so is one whose writer may not approve for its group (intervention_inbox.hpp: not_entitled).
// A source like the others (causal/dds/sample_source.hpp): the one source driver publishes what next() gives.
#pragma once

#include "intervention_inbox.hpp"
#include "level_plant.hpp"
#include "sim_options.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/sample_source.hpp"
#include "causal/dds/source_driver.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace causal::sim {

class PlantNode final : public dds::SampleSource {
 public:
  explicit PlantNode(SimOptions options);
  int run() { return driver_.run(*this); }
  void stop() { driver_.stop(); }
  dds::Take next(dds::SourceDriver& driver, dds::SourceBlock& out) override;
  // Late, overlapping or bad approvals, and those from a writer not entitled to the group: exit 4.
  std::uint64_t refused() const override { return refused_ + interventions_.not_entitled(); }
  void summary(const dds::SourceCounts& counts, bool stopped) const override;

 private:
  struct Group {
    std::string id;
    LevelPlant plant;
  };
  void take_interventions();  // before every snapshot: applies what arrived
  void apply(const causal_twin::Intervention& in);
  dds::Take end();  // after the last snapshot or a stop

  SimOptions options_;
  dds::Participant participant_;
  dds::SourceDriver driver_;
  InterventionInbox interventions_;  // approvals whose writer's grant names their group
  std::vector<Group> groups_;
  std::vector<std::string> channel_names_;
  std::set<std::string> seen_requests_;  // an intervention instance re-sent (transient local) is applied once
  std::uint64_t snapshot_ = 0;      // the snapshot being published
  std::size_t next_group_ = 0;      // its next group
  bool ended_ = false;
  std::uint64_t applied_ = 0, refused_ = 0, other_groups_ = 0;
};

}  // namespace causal::sim
