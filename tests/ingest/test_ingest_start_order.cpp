// The ingest unit gave up when the estimator was not there within 30 s (exit 3) and
// RestartPreventExitStatus=3 kept it dead, so a plant whose sensor host boots first never ingested.
// Checked here:
//  * the shipped units restart on everything but a configuration error (exit 2), up to a start limit that a
//    service failing at once on every start reaches (10 starts in 120 s) and a 30 s peer wait does not; the shipped ingest and sensor options wait for the estimator for as long as it
//    takes (--wait-timeout 0);
//  * sensor-ingest run with the shipped ingest@line1-mqtt.env options (its source swapped for UDP) waits for a
//    "causal-estimator" that comes 12 s later, says so while waiting, and then delivers every block.
// Fixed DDS domain 78.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>
#include <algorithm>

#include "ingest_test_support.hpp"
#include "test_files.hpp"

namespace fs = std::filesystem;
using causal::test::FrameRecorder;
using causal::test::ServiceProcess;

namespace {

constexpr int kDomain = 78;

using causal::test::slurp;

// The value of KEY= in a systemd environment file, split on spaces (as systemd does for $KEY).
std::vector<std::string> env_words(const fs::path& file, const std::string& key) {
  std::istringstream lines(slurp(file));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind(key + "=", 0) != 0) continue;
    std::string value = line.substr(key.size() + 1);
    // systemd EnvironmentFile syntax: a value may be quoted as a whole (the shipped files quote theirs).
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"') value = value.substr(1, value.size() - 2);
    std::istringstream words(value);
    std::vector<std::string> out;
    for (std::string w; words >> w;) out.push_back(w);
    return out;
  }
  return {};
}

}  // namespace

TEST(IngestStartOrder, UnitsRestartOnEverythingButAConfigurationError) {
  const fs::path units = fs::path(CAUSAL_TWIN_DEPLOY_DIR) / "systemd";
  std::size_t checked = 0;
  for (const auto& entry : fs::directory_iterator(units)) {
    if (entry.path().extension() != ".service") continue;
    const std::string unit = slurp(entry.path());
    ++checked;
    EXPECT_NE(unit.find("\nRestart=on-failure\n"), std::string::npos) << entry.path();
    EXPECT_NE(unit.find("\nStartLimitIntervalSec=120\nStartLimitBurst=10\n"), std::string::npos)
        << entry.path() << ": a start limit (a typo must not restart a service every 2 s forever), that a 30 s "
        << "wait for peers (restarted every 32 s) never reaches";
    std::smatch m;
    ASSERT_TRUE(std::regex_search(unit, m, std::regex("\nRestartPreventExitStatus=([^\n]*)\n"))) << entry.path();
    EXPECT_EQ(m[1].str(), "2") << entry.path() << ": only a configuration error may keep a unit down";
  }
  EXPECT_GE(checked, 6u);
  for (const auto& [file, key] : {std::pair<std::string, std::string>{"ingest@line1-mqtt.env", "INGEST_ARGS"},
                                  {"sensor@ims2-slice.env", "SENSOR_ARGS"}}) {
    const auto words = env_words(units / "env" / file, key);
    const auto it = std::find(words.begin(), words.end(), "--wait-timeout");
    ASSERT_NE(it, words.end()) << file << ": the default (30 s) gives up on an estimator that boots later";
    ASSERT_NE(std::next(it), words.end());
    EXPECT_EQ(*std::next(it), "0") << file;
  }
}

TEST(IngestStartOrder, IngestWaitsForAnEstimatorThatComesLaterAndDeliversEverything) {
  const fs::path work = fs::temp_directory_path() / ("causal_ingest_order_" + std::to_string(getpid()));
  fs::create_directories(work);
  const int port = causal::test::free_port(SOCK_DGRAM);
  // The shipped options, with a UDP source instead of the example broker.
  auto args = env_words(fs::path(CAUSAL_TWIN_DEPLOY_DIR) / "systemd" / "env" / "ingest@line1-mqtt.env", "INGEST_ARGS");
  ASSERT_FALSE(args.empty());
  std::vector<std::string> argv = {SENSOR_INGEST_BIN, "--domain", std::to_string(kDomain), "--transport",
                                   std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml", "--max-runtime", "60"};
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--mqtt-qos" || args[i] == "--source") {
      if (args[i] == "--source") argv.insert(argv.end(), {"--source", "udp://127.0.0.1:" + std::to_string(port)});
      ++i;  // and its value
      continue;
    }
    argv.push_back(args[i]);
  }
  ServiceProcess ingest("sensor-ingest", argv, (work / "ingest.log").string());
  // 12 s without an estimator: it must still be waiting, and say so.
  ASSERT_TRUE(ingest.wait_for_output("still waiting for", std::chrono::seconds(15))) << ingest.output();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  ASSERT_TRUE(ingest.running()) << ingest.output();
  EXPECT_EQ(ingest.output().find("ingesting from"), std::string::npos) << ingest.output();

  FrameRecorder estimator(kDomain, "causal-estimator");  // the estimator's host is up at last
  ASSERT_TRUE(ingest.wait_for_output("ingesting from", std::chrono::seconds(20))) << ingest.output();
  constexpr std::size_t kBlocks = 12;
  const std::string group = "late-estimator-pump";
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  for (std::uint64_t k = 0; k < kBlocks; ++k) {
    const std::string m = causal::test::encode(causal::test::stream_block(group, k), 0);
    ASSERT_EQ(::sendto(fd, m.data(), m.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
              static_cast<ssize_t>(m.size()));
  }
  ::close(fd);
  EXPECT_EQ(estimator.wait_for(group, kBlocks, std::chrono::seconds(20)), kBlocks) << ingest.output();
  EXPECT_EQ(ingest.terminate(), 0) << ingest.output();
  std::printf("waited for the estimator, then %zu of %zu blocks delivered as frames\n",
              estimator.frames(group).size(), kBlocks);
  if (!HasFailure()) fs::remove_all(work);
}
