// Where sensor-replay's raw samples come from. A real sensor publisher replaces this with its driver.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace causal::replay {

struct Snapshot {
  std::string name;           // file name or label, published as the frame's `source`
  std::int64_t time_ns = 0;   // UTC time of the first sample
  Eigen::MatrixXd samples;    // N x G (selected channels only)
};

class SnapshotSource {
 public:
  virtual ~SnapshotSource() = default;
  virtual std::size_t size() const = 0;
  // Loads snapshot i with the selected channels. Throws causal::io::InputError on a bad file.
  virtual Snapshot load(std::size_t i) const = 0;
  virtual const std::vector<std::string>& channel_names() const = 0;  // selected channels' names
};

// channels: 1-based selection (empty = all); names: override for the selected channels (empty = default).
std::unique_ptr<SnapshotSource> open_ims_directory(const std::string& dir, const std::vector<int>& channels,
                                                   const std::vector<std::string>& names);
std::unique_ptr<SnapshotSource> open_channel_csv(const std::string& file, const std::vector<int>& channels,
                                                 const std::vector<std::string>& names);

// Column selection shared by the sources: throws std::invalid_argument for a channel outside 1..G.
Eigen::MatrixXd select_channels(const Eigen::MatrixXd& all, const std::vector<int>& channels);
std::vector<std::string> select_names(const std::vector<std::string>& all, const std::vector<int>& channels,
                                      const std::vector<std::string>& override_names);

}  // namespace causal::replay
