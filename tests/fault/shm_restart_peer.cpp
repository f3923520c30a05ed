// shm-restart-peer: the two sides of the shared-memory restart test (test_shm_restart.cpp), through the product's
// own causal::dds::Participant and the shipped profiles (qos.xml, localhost.xml).
//   shm-restart-peer writer DOMAIN BATCH SECONDS
//     publishes BATCH vibration frames (batch b: instance "batch-b", first_sample_index 0..BATCH-1) each time one
//     more reader has matched, until SECONDS have passed; prints "batch b published" after each.
//   shm-restart-peer reader DOMAIN BATCH SECONDS [STALL_AFTER]
//     counts the frames of the first batch it sees; exits 0 once it has all BATCH of them exactly once, 1 when
//     SECONDS pass first. With STALL_AFTER it instead blocks in its data callback after that many frames (the
//     transport's receive thread stays busy: the state of a service killed while taking a message) and prints
//     "stalled", to be killed with SIGKILL.
// Both print "shm_port=P" once the participant exists: the shared-memory port this process listens on, the one
// whose lock file (/dev/shm/fastrtps_port<P>_el) it holds (/proc/locks), or "shm_port=none".
#include "causal/dds/participant.hpp"
#include "causal_twinPubSubTypes.h"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <unistd.h>

namespace {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;
using causal_twin::VibrationFrame;
using causal_twin::VibrationFramePubSubType;

constexpr const char* kTopic = "causal_twin_test/shm_restart";
constexpr std::size_t kSamples = 4096;  // 32 KiB of doubles per frame, the size of a real frame

causal::dds::DdsSettings settings(int domain, const std::string& name) {
  causal::dds::DdsSettings s;
  s.profile_files = {std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/qos.xml",
                     std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml"};
  s.domain_id = domain;
  s.participant_name = name;
  s.ack_stall_s = 0;
  return s;
}

// The shared-memory port whose exclusive-reader lock file this process holds: /proc/locks names the holder's pid
// and the file's inode.
std::string own_shm_port() {
  std::ifstream locks("/proc/locks");
  std::set<unsigned long> inodes;
  const std::string self = std::to_string(getpid());
  for (std::string line; std::getline(locks, line);) {
    std::istringstream in(line);
    std::string id, kind, mode, access, pid, dev_inode;
    in >> id >> kind >> mode >> access >> pid >> dev_inode;
    if (kind != "FLOCK" || pid != self) continue;
    inodes.insert(std::stoul(dev_inode.substr(dev_inode.rfind(':') + 1)));
  }
  for (int port = 7400; port < 65536; ++port) {
    struct stat st {};
    const std::string lock = "/dev/shm/fastrtps_port" + std::to_string(port) + "_el";
    if (stat(lock.c_str(), &st) == 0 && inodes.count(static_cast<unsigned long>(st.st_ino)) > 0) {
      return std::to_string(port);
    }
  }
  return "none";
}

int run_writer(int domain, std::size_t batch, int seconds) {
  causal::dds::Participant participant(settings(domain, "shm-restart-writer"));
  std::cout << "shm_port=" << own_shm_port() << std::endl;
  auto* topic = participant.topic<VibrationFramePubSubType>(kTopic);
  fdds::DataWriterQos qos;
  if (participant.publisher()->get_datawriter_qos_from_profile("vibration_frame_writer", qos) !=
      ReturnCode_t::RETCODE_OK) {
    std::cerr << "no profile vibration_frame_writer" << std::endl;
    return 2;
  }
  auto* writer = participant.publisher()->create_datawriter(topic, qos);
  if (writer == nullptr) return 2;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  int matched_total = 0;  // readers ever matched: one batch each
  while (std::chrono::steady_clock::now() < end) {
    fdds::PublicationMatchedStatus status;
    writer->get_publication_matched_status(status);
    if (status.total_count <= matched_total) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    ++matched_total;
    VibrationFrame frame;
    frame.asset_group("batch-" + std::to_string(matched_total));
    frame.snapshot_index(static_cast<std::uint64_t>(matched_total));
    frame.sample_rate_hz(1000.0);
    frame.channel_names({"c1"});
    frame.unit("V");
    frame.samples_per_channel(static_cast<std::uint32_t>(kSamples));
    frame.samples(std::vector<double>(kSamples, 0.25));
    for (std::size_t i = 0; i < batch; ++i) {
      frame.sequence_number(i);
      frame.first_sample_index(i);
      if (writer->write(&frame, eprosima::fastrtps::rtps::c_InstanceHandle_Unknown) != ReturnCode_t::RETCODE_OK) {
        std::cerr << "write refused in batch " << matched_total << " at " << i << std::endl;
        return 1;
      }
    }
    std::cout << "batch " << matched_total << " published" << std::endl;
  }
  participant.publisher()->delete_datawriter(writer);
  return 0;
}

class CountingListener : public fdds::DataReaderListener {
 public:
  CountingListener(std::size_t batch, long stall_after) : batch_(batch), stall_after_(stall_after) {}

  void on_data_available(fdds::DataReader* reader) override {
    VibrationFrame frame;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&frame, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      std::lock_guard<std::mutex> lock(mutex_);
      ++taken_;
      if (first_batch_ == 0) first_batch_ = frame.snapshot_index();
      if (frame.snapshot_index() == first_batch_) {
        if (!seen_.insert(frame.first_sample_index()).second) ++duplicates_;
      } else {
        ++other_batches_;
      }
      if (stall_after_ > 0 && taken_ >= static_cast<std::size_t>(stall_after_)) {
        std::cout << "stalled after " << taken_ << std::endl;
        // The receive thread stays here, busy with a message, until the test kills the process.
        while (true) std::this_thread::sleep_for(std::chrono::seconds(1));
      }
    }
  }

  bool complete() {
    std::lock_guard<std::mutex> lock(mutex_);
    return seen_.size() == batch_;
  }

  std::string summary() {
    std::lock_guard<std::mutex> lock(mutex_);
    return "batch=" + std::to_string(first_batch_) + " received=" + std::to_string(seen_.size()) +
           " duplicates=" + std::to_string(duplicates_) + " other_batches=" + std::to_string(other_batches_);
  }

 private:
  std::mutex mutex_;
  std::size_t batch_;
  long stall_after_;
  std::size_t taken_ = 0;
  std::uint64_t first_batch_ = 0;
  std::set<std::uint64_t> seen_;
  std::size_t duplicates_ = 0;
  std::size_t other_batches_ = 0;
};

int run_reader(int domain, std::size_t batch, int seconds, long stall_after) {
  causal::dds::Participant participant(settings(domain, "shm-restart-reader"));
  std::cout << "shm_port=" << own_shm_port() << std::endl;
  auto* topic = participant.topic<VibrationFramePubSubType>(kTopic);
  fdds::DataReaderQos qos;
  if (participant.subscriber()->get_datareader_qos_from_profile("vibration_frame_reader", qos) !=
      ReturnCode_t::RETCODE_OK) {
    std::cerr << "no profile vibration_frame_reader" << std::endl;
    return 2;
  }
  CountingListener listener(batch, stall_after);
  auto* reader = participant.subscriber()->create_datareader(topic, qos, &listener);
  if (reader == nullptr) return 2;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  while (!listener.complete() && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const bool complete = listener.complete();
  std::cout << "shm-restart-peer reader: " << listener.summary() << std::endl;
  participant.subscriber()->delete_datareader(reader);
  return complete ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: shm-restart-peer writer|reader DOMAIN BATCH SECONDS [STALL_AFTER]" << std::endl;
    return 2;
  }
  const std::string role = argv[1];
  const int domain = std::stoi(argv[2]);
  const auto batch = static_cast<std::size_t>(std::stoul(argv[3]));
  const int seconds = std::stoi(argv[4]);
  if (role == "writer") return run_writer(domain, batch, seconds);
  if (role == "reader") return run_reader(domain, batch, seconds, argc > 5 ? std::stol(argv[5]) : 0);
  std::cerr << "shm-restart-peer: unknown role '" << role << "'" << std::endl;
  return 2;
}
