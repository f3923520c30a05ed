// sensor-ingest against real sources: a real mosquitto broker on loopback (started after the adapter,
// restarted mid-run), UDP datagrams and stdin. Every test sends N good blocks in all three encodings and
// one bad message of every rejection class, and checks exactly: N frames out with gap-free sequence numbers
// and the samples sent, every bad message counted under its reason, exit code 4 (something was rejected).
#include <cstdlib>
#include <gtest/gtest.h>
#include <mosquitto.h>

#include <filesystem>
#include <iostream>

#include "ingest_test_support.hpp"
#include "test_files.hpp"

namespace fs = std::filesystem;
using causal::test::FrameRecorder;
using causal::test::ServiceProcess;

namespace {

// A fixed domain id of this helper's range (82-83; 82 is the end-to-end test's). The tests here may run at
// once on it: each has its own asset group and its own recorder, which its adapter waits for by name.
constexpr int kDomain = 83;

fs::path work_dir(const std::string& name) { return causal::test::fresh_work_dir("causal_ingest", name); }

// The adapter on kDomain, waiting for the test's own recorder (by its participant name) before taking input.
std::vector<std::string> ingest_args(const std::string& recorder, const std::string& source) {
  // clang-format off
  return {SENSOR_INGEST_BIN, "--domain", std::to_string(kDomain), "--wait-for", recorder,
          "--transport", std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml", "--source", source,
          "--max-block-values", "1000", "--max-runtime", "90", "--wait-timeout", "30"};
  // clang-format on
}

// Frames of `group`: sequence 0..n-1 in order, samples counted from 0, the sample values of stream_block(k),
// a discontinuity only on the first.
void expect_stream(const std::vector<causal::test::SeenFrame>& frames, const std::string& group, std::size_t n) {
  ASSERT_EQ(frames.size(), n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto b = causal::test::stream_block(group, k);
    const auto& f = frames[k];
    EXPECT_EQ(f.sequence, k);
    EXPECT_EQ(f.first_sample_index, 50 * k);
    EXPECT_EQ(f.snapshot_index, 0u);
    EXPECT_EQ(f.time_ns, b.t0_ns);
    EXPECT_EQ(f.discontinuity, k == 0) << "frame " << k;
    ASSERT_EQ(f.samples.size(), 100u);
    EXPECT_EQ(f.samples.front(), b.first_value);
    EXPECT_EQ(f.samples.back(), b.first_value + 99.0);
  }
}

void expect_rejections(const std::string& output, const std::vector<std::pair<std::string, std::string>>& bad,
                       std::size_t good) {
  const auto at = output.rfind("sensor-ingest: received=");
  ASSERT_NE(at, std::string::npos) << output;
  std::cout << output.substr(at, output.find('\n', at) - at) << "\n";
  const auto counts = causal::test::summary_counts(output);
  std::map<std::string, std::uint64_t> expected;
  for (const auto& b : bad) ++expected[b.first];
  EXPECT_EQ(counts.at("received"), good + bad.size());
  EXPECT_EQ(counts.at("published"), good);
  EXPECT_EQ(counts.at("rejected"), bad.size());
  EXPECT_EQ(counts.at("lost"), 0u);
  for (const auto& [reason, n] : expected) EXPECT_EQ(counts.at(reason), n) << reason;
}

class Broker {
 public:
  Broker(const fs::path& dir, int port) : dir_(dir), port_(port) {
    std::ofstream(dir / "mosquitto.conf")
        << "listener " << port << " 127.0.0.1\nallow_anonymous true\npersistence false\n";
  }
  void start(int run) {
    process_ = std::make_unique<ServiceProcess>(
        "mosquitto", std::vector<std::string>{"/usr/sbin/mosquitto", "-c", (dir_ / "mosquitto.conf").string()},
        (dir_ / ("mosquitto" + std::to_string(run) + ".log")).string());
  }
  void kill() { process_->kill_hard(); }
  int port() const { return port_; }

 private:
  fs::path dir_;
  int port_;
  std::unique_ptr<ServiceProcess> process_;
};

// Publishes messages with QoS 1 and returns once the broker acknowledged every one (PUBACK).
bool publish_all(int port, const std::string& topic, const std::vector<std::string>& messages) {
  mosquitto_lib_init();
  std::atomic<int> acked{0};
  mosquitto* m = mosquitto_new(nullptr, true, &acked);
  mosquitto_publish_callback_set(m, [](mosquitto*, void* count, int) { ++*static_cast<std::atomic<int>*>(count); });
  bool ok = false;
  for (int attempt = 0; attempt < 50 && !ok; ++attempt) {  // the broker may still be starting
    ok = mosquitto_connect(m, "127.0.0.1", port, 30) == MOSQ_ERR_SUCCESS;
    if (!ok) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (ok) {
    mosquitto_loop_start(m);
    for (const auto& msg : messages) {
      ok = ok && mosquitto_publish(m, nullptr, topic.c_str(), static_cast<int>(msg.size()), msg.data(), 1, false) ==
                     MOSQ_ERR_SUCCESS;
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (acked.load() < static_cast<int>(messages.size()) && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ok = ok && acked.load() == static_cast<int>(messages.size());
    mosquitto_disconnect(m);
    mosquitto_loop_stop(m, false);
  }
  mosquitto_destroy(m);
  return ok;
}

}  // namespace

TEST(SensorIngest, MqttBlocksBecomeFramesAcrossABrokerStartedLateAndRestarted) {
  if (!fs::exists("/usr/sbin/mosquitto")) {
    // deploy/test.sh (CI) installs the broker and sets CAUSAL_TWIN_REQUIRE_ALL: there a missing broker fails.
    if (std::getenv("CAUSAL_TWIN_REQUIRE_ALL") != nullptr)
      FAIL() << "no mosquitto broker at /usr/sbin/mosquitto (deploy/test.sh requires it)";
    GTEST_SKIP() << "no mosquitto broker (deploy/install_deps.sh installs it)";
  }
  const fs::path work = work_dir("mqtt");
  const std::string group = "mqtt-pump";
  const std::string topic = "plant/line1/" + group;
  Broker broker(work, causal::test::free_port(SOCK_STREAM));
  FrameRecorder recorder(kDomain, "ingest-test-mqtt");
  ServiceProcess ingest("sensor-ingest",
                        ingest_args("ingest-test-mqtt", "mqtt://127.0.0.1:" + std::to_string(broker.port()) + "/" + topic),
                        (work / "ingest.log").string());
  // The adapter may start before its broker: it keeps trying.
  ASSERT_TRUE(ingest.wait_for_output("cannot connect", std::chrono::seconds(40))) << ingest.output();
  broker.start(1);
  ASSERT_TRUE(ingest.wait_for_output("(connection 1)", std::chrono::seconds(40))) << ingest.output();

  constexpr std::size_t kFirst = 12, kSecond = 9;
  std::vector<std::string> messages;
  for (std::uint64_t k = 0; k < kFirst; ++k)
    messages.push_back(causal::test::encode(causal::test::stream_block(group, k), static_cast<int>(k % 3)));
  const auto bad = causal::test::bad_messages(group, kFirst - 1);
  for (const auto& b : bad) messages.push_back(b.second);
  ASSERT_TRUE(publish_all(broker.port(), topic, messages));
  ASSERT_EQ(recorder.wait_for(group, kFirst, std::chrono::seconds(30)), kFirst) << ingest.output();

  // The broker dies and comes back on the same port: the adapter reconnects and subscribes again by itself.
  broker.kill();
  ASSERT_TRUE(ingest.wait_for_output("lost the broker", std::chrono::seconds(20))) << ingest.output();
  broker.start(2);
  ASSERT_TRUE(ingest.wait_for_output("(connection 2)", std::chrono::seconds(30))) << ingest.output();
  messages.clear();
  for (std::uint64_t k = kFirst; k < kFirst + kSecond; ++k) {
    messages.push_back(causal::test::encode(causal::test::stream_block(group, k), static_cast<int>(k % 3)));
  }
  ASSERT_TRUE(publish_all(broker.port(), topic, messages));
  ASSERT_EQ(recorder.wait_for(group, kFirst + kSecond, std::chrono::seconds(30)), kFirst + kSecond) << ingest.output();

  EXPECT_EQ(ingest.terminate(), 4) << ingest.output();  // 4: messages were rejected
  expect_stream(recorder.frames(group), group, kFirst + kSecond);
  expect_rejections(ingest.output(), bad, kFirst + kSecond);
  broker.kill();
  if (!HasFailure()) fs::remove_all(work);
}

TEST(SensorIngest, UdpDatagramsBecomeFrames) {
  const fs::path work = work_dir("udp");
  const std::string group = "udp-pump";
  const int port = causal::test::free_port(SOCK_DGRAM);
  FrameRecorder recorder(kDomain, "ingest-test-udp");
  ServiceProcess ingest("sensor-ingest", ingest_args("ingest-test-udp", "udp://127.0.0.1:" + std::to_string(port)),
                        (work / "ingest.log").string());
  ASSERT_TRUE(ingest.wait_for_output("ingesting from", std::chrono::seconds(40))) << ingest.output();

  constexpr std::size_t kGood = 15;
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const auto send = [&](const std::string& m) {
    ASSERT_EQ(::sendto(fd, m.data(), m.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
              static_cast<ssize_t>(m.size()));
  };
  for (std::uint64_t k = 0; k < kGood; ++k)
    send(causal::test::encode(causal::test::stream_block(group, k), static_cast<int>(k % 3)));
  const auto bad = causal::test::bad_messages(group, kGood - 1);
  for (const auto& b : bad) send(b.second);
  ::close(fd);
  ASSERT_EQ(recorder.wait_for(group, kGood, std::chrono::seconds(30)), kGood) << ingest.output();
  // Every datagram is taken before the stop (the bad ones came last): wait until the adapter logged the last.
  ASSERT_TRUE(ingest.wait_for_output("rejected (out_of_order)", std::chrono::seconds(10)))
      << ingest.output();

  EXPECT_EQ(ingest.terminate(), 4) << ingest.output();
  expect_stream(recorder.frames(group), group, kGood);
  expect_rejections(ingest.output(), bad, kGood);
  if (!HasFailure()) fs::remove_all(work);
}

TEST(SensorIngest, StdinStreamBecomesFramesAndEndsAtEndOfInput) {
  const fs::path work = work_dir("stdin");
  const std::string group = "stdin-pump";
  constexpr std::size_t kGood = 15;
  std::string stream;
  for (std::uint64_t k = 0; k < kGood; ++k)
    stream += causal::test::encode(causal::test::stream_block(group, k), static_cast<int>(k % 3)) + "\n";
  // The truncated binary block goes last: in a byte stream it would take the next message's bytes with it.
  auto bad = causal::test::bad_messages(group, kGood - 1);
  std::stable_partition(bad.begin(), bad.end(), [](const auto& b) { return b.first != "truncated"; });
  for (const auto& b : bad) stream += b.second + (b.first == "truncated" ? "" : "\n");
  std::ofstream(work / "input.bin", std::ios::binary) << stream;

  FrameRecorder recorder(kDomain, "ingest-test-stdin");
  std::string command = "exec";
  for (const auto& a : ingest_args("ingest-test-stdin", "-")) command += " '" + a + "'";
  command += " < '" + (work / "input.bin").string() + "'";
  ServiceProcess ingest("sensor-ingest", {"/bin/sh", "-c", command}, (work / "ingest.log").string());
  const auto code = ingest.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value()) << "sensor-ingest did not end at end of input:\n" << ingest.output();
  EXPECT_EQ(*code, 4) << ingest.output();
  EXPECT_EQ(recorder.wait_for(group, kGood, std::chrono::seconds(10)), kGood);
  expect_stream(recorder.frames(group), group, kGood);
  expect_rejections(ingest.output(), bad, kGood);
  if (!HasFailure()) fs::remove_all(work);
}
