// Helpers of the sensor-ingest integration tests: a DDS reader that records every vibration frame per asset
// group, block encoders written from the --help text (not from the adapter's parser), free loopback ports,
// and a real mosquitto broker started and ended by pid.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"
#include "free_port.hpp"
#include "loopback_settings.hpp"
#include "process_runner.hpp"

namespace causal::test {

struct SeenFrame {
  std::string unit;
  double sample_rate_hz;
  std::vector<std::string> channel_names;
  std::uint64_t sequence, first_sample_index, snapshot_index, samples_per_channel;
  std::int64_t time_ns;
  bool discontinuity, end_of_segment;
  std::vector<double> samples;
};

// One CausalFactors message: (time scale, kind, outcome, sample index) -> factors, then their std.
using FactorKey = std::tuple<int, int, int, std::uint64_t>;
struct SeenFactors {
  std::vector<double> factors, factor_std;
  std::int64_t time_ns;
};

class FrameRecorder {
 public:
  // `name`: the participant name, unique per test, so an adapter can wait for this very reader (--wait-for).
  FrameRecorder(int domain_id, const std::string& name)
      : participant_(settings(domain_id, name)),
        reader_(participant_, dds::topics::kVibrationFrame, dds::profiles::kVibrationFrameReader),
        factor_reader_(participant_, dds::topics::kCausalFactors, dds::profiles::kCausalFactorsReader),
        thread_([this] { run(); }) {}
  ~FrameRecorder() {
    stop_.store(true);
    thread_.join();
  }
  std::vector<SeenFrame> frames(const std::string& group) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = frames_.find(group);
    return it == frames_.end() ? std::vector<SeenFrame>{} : it->second;
  }
  std::map<FactorKey, SeenFactors> factors(const std::string& group) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = factors_.find(group);
    return it == factors_.end() ? std::map<FactorKey, SeenFactors>{} : it->second;
  }
  // Waits (bounded) until `group` has at least `count` frames; returns how many it has.
  std::size_t wait_for(const std::string& group, std::size_t count, std::chrono::seconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (frames(group).size() < count && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return frames(group).size();
  }

 private:
  static dds::DdsSettings settings(int domain_id, const std::string& name) {
    return causal::test::loopback_settings(domain_id, name);
  }
  void run() {
    while (!stop_.load()) {
      reader_.take_all([this](const causal_twin::VibrationFrame& f, const auto&) {
        std::lock_guard<std::mutex> lock(mutex_);
        frames_[f.asset_group()].push_back(SeenFrame{f.unit(),
                                                     f.sample_rate_hz(),
                                                     {f.channel_names().begin(), f.channel_names().end()},
                                                     f.sequence_number(),
                                                     f.first_sample_index(),
                                                     f.snapshot_index(),
                                                     f.samples_per_channel(),
                                                     f.first_sample_time_ns(),
                                                     f.discontinuity(),
                                                     f.end_of_segment(),
                                                     f.samples()});
      });
      factor_reader_.take_all([this](const causal_twin::CausalFactorBatch& f, const auto&) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& block : f.outcomes()) {
          factors_[f.asset_group()][FactorKey{static_cast<int>(f.time_scale()), static_cast<int>(f.kind()),
                                              block.outcome(), f.sample_index()}] =
              SeenFactors{block.factors(), block.factor_std(), f.time_ns()};
        }
      });
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  dds::Participant participant_;
  dds::TypedReader<causal_twin::VibrationFramePubSubType> reader_;
  dds::TypedReader<causal_twin::CausalFactorBatchPubSubType> factor_reader_;
  mutable std::mutex mutex_;
  std::map<std::string, std::vector<SeenFrame>> frames_;
  std::map<std::string, std::map<FactorKey, SeenFactors>> factors_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// ---- encoders, as documented in sensor-ingest --help ------------------------------------------------------

struct TestBlock {
  std::string group;
  std::uint64_t sequence;
  std::int64_t t0_ns;
  std::size_t n;       // samples per channel; channels are always c1, c2
  double first_value;  // samples are first_value, first_value + 1, ... sample-major
};

inline std::string json_block(const TestBlock& b) {
  std::string rows;
  for (std::size_t i = 0; i < b.n; ++i) {
    rows += (i ? "," : "") + std::string("[") + std::to_string(b.first_value + 2.0 * static_cast<double>(i)) + "," +
            std::to_string(b.first_value + 2.0 * static_cast<double>(i) + 1) + "]";
  }
  return R"({"asset_group":")" + b.group + R"(","channels":["c1","c2"],"sample_rate_hz":1000,"t0_ns":)" +
         std::to_string(b.t0_ns) + R"(,"sequence":)" + std::to_string(b.sequence) + R"(,"samples":[)" + rows + "]}";
}

inline std::string csv_block(const TestBlock& b) {
  std::string s = "#block asset_group=" + b.group +
                  " channels=c1,c2 sample_rate_hz=1000 t0_ns=" + std::to_string(b.t0_ns) +
                  " sequence=" + std::to_string(b.sequence) + " samples=" + std::to_string(b.n) + "\n";
  for (std::size_t i = 0; i < b.n; ++i) {
    s += std::to_string(b.first_value + 2.0 * static_cast<double>(i)) + "," + std::to_string(b.first_value + 2.0 * static_cast<double>(i) + 1) + "\n";
  }
  return s;
}

inline void put_le(std::string& s, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
inline void put_name(std::string& s, const std::string& t) {
  put_le(s, t.size(), 2);
  s += t;
}
inline std::string binary_block(const TestBlock& b) {
  std::string s = "CTB1";
  put_le(s, 2, 2);
  put_le(s, 0, 2);
  put_le(s, b.n, 4);
  put_le(s, b.sequence, 8);
  put_le(s, static_cast<std::uint64_t>(b.t0_ns), 8);
  const double rate = 1000.0;
  std::uint64_t bits = 0;
  std::memcpy(&bits, &rate, 8);
  put_le(s, bits, 8);
  put_name(s, b.group);
  put_name(s, "g");
  put_name(s, "c1");
  put_name(s, "c2");
  for (std::size_t i = 0; i < 2 * b.n; ++i) {
    const double v = b.first_value + static_cast<double>(i);
    std::memcpy(&bits, &v, 8);
    put_le(s, bits, 8);
  }
  return s;
}

// Block k of a contiguous 1 kHz stream of 50-sample blocks, in encoding k % 3 (JSON, CSV, binary).
inline TestBlock stream_block(const std::string& group, std::uint64_t k) {
  return TestBlock{group, k, 1700000000000000000LL + static_cast<std::int64_t>(k) * 50000000LL, 50,
                   100.0 * static_cast<double>(k)};
}
inline std::string encode(const TestBlock& b, int encoding) {
  return encoding == 0 ? json_block(b) : encoding == 1 ? csv_block(b) : binary_block(b);
}

// The bad messages every test sends after good blocks 0..last: one per rejection class, by reason.
inline std::vector<std::pair<std::string, std::string>> bad_messages(const std::string& group, std::uint64_t last) {
  const std::string bin = binary_block(stream_block(group, last + 1));
  std::string wrong_channels = json_block(stream_block(group, last + 1));
  wrong_channels.replace(wrong_channels.find("[\"c1\",\"c2\"]"), 11, "[\"c1\",\"c2\",\"c3\"]");
  TestBlock back_in_time = stream_block(group, 0);
  back_in_time.sequence = last + 100;
  return {{"malformed", R"({"asset_group":")" + group + R"(","channels":)"},  // cut-off JSON
          {"malformed", "temperature=21.5"},
          {"shape", wrong_channels},  // 3 channel names, rows of 2
          {"truncated", bin.substr(0, bin.size() - 3)},
          {"oversize", json_block(TestBlock{group, last + 1, 0, 600, 0.0})},  // 1200 values > --max-block-values 1000
          {"duplicate", csv_block(stream_block(group, last))},                // the last block again (QoS 1 redelivery)
          {"out_of_order", json_block(back_in_time)}};                        // starts before the last block ended
}

// The adapter's machine-readable summary line, e.g. "received=7 published=5 ... malformed=1".
inline std::map<std::string, std::uint64_t> summary_counts(const std::string& output) {
  return counts_in_last_line(output, "sensor-ingest: received=");
}

}  // namespace causal::test
