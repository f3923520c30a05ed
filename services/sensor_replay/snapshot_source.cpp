#include "snapshot_source.hpp"

#include "causal/io/time_format.hpp"

#include "causal/io/channel_csv.hpp"
#include "causal/io/ims_directory.hpp"

#include <chrono>
#include <stdexcept>

namespace causal::replay {

Eigen::MatrixXd select_channels(const Eigen::MatrixXd& all, const std::vector<int>& channels) {
  if (channels.empty()) return all;
  Eigen::MatrixXd out(all.rows(), static_cast<Eigen::Index>(channels.size()));
  for (std::size_t c = 0; c < channels.size(); ++c) {
    if (channels[c] < 1 || channels[c] > all.cols()) {
      throw std::invalid_argument("channel " + std::to_string(channels[c]) + " does not exist: the source has " +
                                  std::to_string(all.cols()) + " channels");
    }
    out.col(static_cast<Eigen::Index>(c)) = all.col(channels[c] - 1);
  }
  return out;
}

std::vector<std::string> select_names(const std::vector<std::string>& all, const std::vector<int>& channels,
                                      const std::vector<std::string>& override_names) {
  std::vector<std::string> out;
  if (channels.empty()) {
    out = all;
  } else {
    for (int c : channels) {
      if (c < 1 || static_cast<std::size_t>(c) > all.size()) {
        throw std::invalid_argument("channel " + std::to_string(c) + " does not exist: the source has " +
                                    std::to_string(all.size()) + " channels");
      }
      out.push_back(all[static_cast<std::size_t>(c - 1)]);
    }
  }
  if (!override_names.empty()) {
    if (override_names.size() != out.size()) {
      throw std::invalid_argument(std::to_string(override_names.size()) + " channel names given for " +
                                  std::to_string(out.size()) + " channels");
    }
    out = override_names;
  }
  return out;
}

namespace {

class ImsDirectorySource final : public SnapshotSource {
 public:
  ImsDirectorySource(const std::string& dir, std::vector<int> channels, const std::vector<std::string>& names)
      : listing_(io::list_ims_directory(dir)), channels_(std::move(channels)) {
    // Channel count from the first file; every later file must match (read_ims_snapshot checks).
    const Eigen::MatrixXd first = io::read_ims_snapshot(listing_.snapshots.front().path);
    columns_ = static_cast<int>(first.cols());
    std::vector<std::string> defaults;
    for (int c = 1; c <= columns_; ++c) defaults.push_back("bearing" + std::to_string(c));
    names_ = select_names(defaults, channels_, names);
  }
  std::size_t size() const override { return listing_.snapshots.size(); }
  Snapshot load(std::size_t i) const override {
    const auto& info = listing_.snapshots.at(i);
    return {info.name, info.time_ns, select_channels(io::read_ims_snapshot(info.path, columns_), channels_)};
  }
  const std::vector<std::string>& channel_names() const override { return names_; }

 private:
  io::ImsListing listing_;
  std::vector<int> channels_;
  int columns_ = 0;
  std::vector<std::string> names_;
};

class ChannelCsvSource final : public SnapshotSource {
 public:
  ChannelCsvSource(const std::string& file, const std::vector<int>& channels, const std::vector<std::string>& names)
      : name_(file) {
    io::ChannelTable table = io::read_channel_csv(file);
    samples_ = select_channels(table.values, channels);
    names_ = select_names(table.channel_names, channels, names);
    // Without a time column the recording is stamped with the start of the replay.
    time_ns_ = table.time_ns.empty() ? io::utc_now_ns() : table.time_ns.front();
  }
  std::size_t size() const override { return 1; }
  Snapshot load(std::size_t) const override { return {name_, time_ns_, samples_}; }
  const std::vector<std::string>& channel_names() const override { return names_; }

 private:
  std::string name_;
  std::int64_t time_ns_ = 0;
  Eigen::MatrixXd samples_;
  std::vector<std::string> names_;
};

}  // namespace

std::unique_ptr<SnapshotSource> open_ims_directory(const std::string& dir, const std::vector<int>& channels,
                                                   const std::vector<std::string>& names) {
  return std::make_unique<ImsDirectorySource>(dir, channels, names);
}

std::unique_ptr<SnapshotSource> open_channel_csv(const std::string& file, const std::vector<int>& channels,
                                                 const std::vector<std::string>& names) {
  return std::make_unique<ChannelCsvSource>(file, channels, names);
}

}  // namespace causal::replay
