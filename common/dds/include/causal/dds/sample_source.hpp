// One skeleton for every source of plant data (sensor-replay, sensor-sim, sensor-ingest, a new adapter): a
// SampleSource says what comes next; the SourceDriver (source_driver.hpp) does the rest the same way for all of
// them: waiting for the readers, pausing when they go, numbering frames, building and writing the frames and
// condition vectors, pacing, telling the source when a restarted reader needs data again, the final
// acknowledgement wait and the exit code. A new adapter (features over MQTT, OPC UA, a historian replay) is one
// class implementing next(); docs/architecture.md ("Sources") has an example.
#pragma once

#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twin.h"

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <string>

namespace causal::dds {

class SourceDriver;

// One piece of plant data for one asset group, as the source hands it to the driver.
struct SourceBlock {
  enum class Kind {
    Frame,      // rows [first_row, first_row + rows) of *samples, under `frame`
    Condition,  // `values` under `condition` (one condition vector)
    Kept,       // *kept: a frame published before, resent unchanged (a live source's backlog)
  };
  Kind kind = Kind::Frame;
  // Frame: the header. Unless `numbered`, the driver sets sequence and first_sample_index: gap-free per asset
  // group, a lost frame still using its numbers (the readers see the gap).
  FrameHeader frame;
  bool numbered = false;
  const Eigen::MatrixXd* samples = nullptr;  // N x G, owned by the source, valid until the next call of next()
  Eigen::Index first_row = 0;
  Eigen::Index rows = 0;
  ConditionHeader condition;
  Eigen::VectorXd values;
  const causal_twin::VibrationFrame* kept = nullptr;
};

// What next() produced.
enum class Take {
  Block,  // `out` holds a block to publish
  Idle,   // nothing this time (a live source waited briefly): the driver looks after its readers and asks again
  End,    // the source is done (or stopping)
};

// Per asset group, the last snapshot index the estimators published (causal_twin/condition_vector): where a
// restarted estimator's checkpoint ends.
using PublishedSnapshots = std::map<std::string, std::uint64_t>;

// What the driver published, for the source's summary.
struct SourceCounts {
  std::uint64_t frames = 0;      // new frames the readers accepted
  std::uint64_t conditions = 0;  // condition vectors the readers accepted
  std::uint64_t lost = 0;        // writes the readers did not accept in time (exit 4)
  std::uint64_t resent = 0;      // kept frames resent to a restarted reader
};

class SampleSource {
 public:
  virtual ~SampleSource() = default;
  // Once the readers are there, before the first next(): open the input, log what will be published.
  // Throws io::InputError or std::invalid_argument on bad input (exit 1).
  virtual void start(SourceDriver& /*driver*/) {}
  // The next block into `out`. Pacing (driver.pace), a rewind for a restarted reader (driver.restarted) happen
  // here, where the source knows its boundaries. May throw like start().
  virtual Take next(SourceDriver& driver, SourceBlock& out) = 0;
  // After every write of a block: `built` is the frame as written (Frame and Kept), else nullptr.
  virtual void written(const SourceBlock& /*block*/, WriteResult /*result*/,
                       const causal_twin::VibrationFrame* /*built*/) {}
  // From the signal thread: a source blocked in next() (a live queue) returns.
  virtual void stop() {}
  // Input the source refused (counted and logged by it): exit 4 when > 0.
  virtual std::uint64_t refused() const { return 0; }
  // The source's summary lines, at the end (also after a failed wait for readers).
  virtual void summary(const SourceCounts& /*counts*/, bool /*stopped*/) const {}
};

}  // namespace causal::dds
