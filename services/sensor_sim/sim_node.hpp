// sensor-sim's frame source: N simulated asset groups (svar_generator.hpp) published round-robin on the
// vibration-frame topic through the one source driver (causal/dds/source_driver.hpp), which numbers the frames,
// writes them and waits for the readers. It publishes until --frames-per-group, --max-runtime or stop() (from
// the signal thread), whichever comes first. Exit codes: 0 done, 3 no readers in time, 4 frames lost (a write
// failed or timed out).
#pragma once

#include "sim_options.hpp"
#include "svar_generator.hpp"

#include "causal/dds/participant.hpp"
#include "causal/dds/sample_source.hpp"
#include "causal/dds/source_driver.hpp"

#include <cstdint>
#include <vector>

namespace causal::sim {

// The driver's options for both sensor-sim modes (frames, or condition vectors with --plant).
dds::SourceDriverOptions driver_options(const SimOptions& options, bool frames);

class SvarFrames final : public dds::SampleSource {
 public:
  explicit SvarFrames(SimOptions& options);
  void start(dds::SourceDriver& driver) override;
  dds::Take next(dds::SourceDriver& driver, dds::SourceBlock& out) override;
  void written(const dds::SourceBlock& block, dds::WriteResult result, const causal_twin::VibrationFrame*) override;
  void summary(const dds::SourceCounts& counts, bool stopped) const override;

 private:
  struct Group {
    SvarGenerator generator;
    dds::FrameHeader header;  // the group's fixed fields; the driver numbers every frame
    std::uint64_t sent = 0;
  };

  SimOptions& options_;
  const dds::SourceDriver* driver_ = nullptr;
  std::vector<Group> groups_;
  std::uint64_t round_ = 0;
  std::size_t next_group_ = 0;
  Eigen::MatrixXd block_;
};

class SimNode {
 public:
  explicit SimNode(SimOptions options);
  int run() { return driver_.run(source_); }
  void stop() { driver_.stop(); }

 private:
  SimOptions options_;
  dds::Participant participant_;
  dds::SourceDriver driver_;
  SvarFrames source_;
};

}  // namespace causal::sim
