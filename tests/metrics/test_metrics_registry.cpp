// causal_metrics (common/metrics): the Prometheus text exposition against hand-written expected text, the
// histogram's cumulative buckets against hand-counted values, callbacks that disappear with their owner, name
// validation, Debian's `promtool check metrics` on the output, and the HTTP endpoint.
#include "causal/metrics/metrics_registry.hpp"
#include "causal/metrics/metrics_server.hpp"
#include "free_port.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <stdexcept>
#include <string>
#include <sys/socket.h>
#include <netinet/in.h>
#include <arpa/inet.h>
#include <unistd.h>

using namespace causal::metrics;

namespace {

// A minimal HTTP/1.0 GET over a socket: the test must not share code with the server it checks.
std::string http_get(int port, const std::string& path) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return "";
  }
  const std::string req = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
  if (::write(fd, req.data(), req.size()) != static_cast<ssize_t>(req.size())) {
    ::close(fd);
    return "";
  }
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  ::close(fd);
  return out;
}

using causal::test::free_port;

TEST(MetricsRegistry, ExpositionOfCountersGaugesAndLabels) {
  MetricsRegistry r;
  r.counter("frames_total", "Frames in", {{"topic", "a/b"}}).inc(3);
  r.counter("frames_total", "Frames in", {{"topic", "a/b"}}).inc();  // same object
  r.counter("frames_total", "Frames in", {{"topic", "q\"\\\n"}}).inc(2);
  r.gauge("depth", "Queue depth").set(7.5);
  r.counter("frames_total", "Frames in", {{"topic", "a/b"}}).inc(-5);  // ignored: counters only go up
  EXPECT_EQ(r.exposition(),
            "# HELP causal_twin_depth Queue depth\n"
            "# TYPE causal_twin_depth gauge\n"
            "causal_twin_depth 7.5\n"
            "# HELP causal_twin_frames_total Frames in\n"
            "# TYPE causal_twin_frames_total counter\n"
            "causal_twin_frames_total{topic=\"a/b\"} 4\n"
            "causal_twin_frames_total{topic=\"q\\\"\\\\\\n\"} 2\n");
}

TEST(MetricsRegistry, HistogramBucketsAreCumulativeWithLeInclusive) {
  MetricsRegistry r;
  auto& h = r.histogram("latency_seconds", "Latency", {{"group", "g1"}}, {0.1, 1.0});
  for (double v : {0.05, 0.1, 0.5, 1.0, 3.0}) h.observe(v);
  h.observe(std::nan(""));  // ignored
  // <= 0.1: 0.05, 0.1 -> 2; <= 1: + 0.5, 1.0 -> 4; +Inf: 5. Sum 4.65.
  const std::string text = r.exposition();
  EXPECT_NE(text.find("causal_twin_latency_seconds_bucket{group=\"g1\",le=\"0.1\"} 2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("causal_twin_latency_seconds_bucket{group=\"g1\",le=\"1\"} 4\n"), std::string::npos);
  EXPECT_NE(text.find("causal_twin_latency_seconds_bucket{group=\"g1\",le=\"+Inf\"} 5\n"), std::string::npos);
  EXPECT_NE(text.find("causal_twin_latency_seconds_sum{group=\"g1\"} 4.65\n"), std::string::npos);
  EXPECT_NE(text.find("causal_twin_latency_seconds_count{group=\"g1\"} 5\n"), std::string::npos);
}

TEST(MetricsRegistry, CallbacksAreReadAtScrapeAndGoneWithTheirHandle) {
  MetricsRegistry r;
  double depth = 3;
  {
    CallbackHandle h = r.gauge_callback("queue_depth", "Depth", {}, [&depth] { return depth; });
    depth = 9;
    EXPECT_NE(r.exposition().find("causal_twin_queue_depth 9\n"), std::string::npos);
  }
  EXPECT_EQ(r.exposition().find("causal_twin_queue_depth"), std::string::npos);
  CallbackHandle lost = r.counter_callback("lost_total", "Lost", {{"topic", "t"}}, [] { return 12.0; });
  EXPECT_NE(r.exposition().find("# TYPE causal_twin_lost_total counter\ncausal_twin_lost_total{topic=\"t\"} 12\n"),
            std::string::npos);
}

TEST(MetricsRegistry, InvalidNamesAndTypeClashesAreRefused) {
  MetricsRegistry r;
  EXPECT_THROW(r.counter("frames", "no _total"), std::invalid_argument);
  EXPECT_THROW(r.gauge("9lives", "digit first"), std::invalid_argument);
  EXPECT_THROW(r.gauge("ok", "bad label", {{"le", "1"}}), std::invalid_argument);
  EXPECT_THROW(r.gauge("ok", "bad label", {{"a-b", "1"}}), std::invalid_argument);
  r.gauge("depth", "d");
  EXPECT_THROW(r.histogram("depth", "d", {}, {1.0}), std::invalid_argument);
  EXPECT_THROW(r.histogram("h", "h", {}, {1.0, 0.5}), std::invalid_argument);
}

// The value of the sample line starting with `name ` in an exposition, NaN when there is none.
double sample_value(const std::string& text, const std::string& name) {
  const auto at = text.find("\n" + name + " ");
  if (at == std::string::npos) return std::nan("");
  return std::stod(text.substr(at + name.size() + 2));
}

TEST(MetricsRegistry, ProcessRegistryHasBuildInfoAndProcessMetrics) {
  const std::string text = process_metrics().exposition();
  EXPECT_NE(text.find("# TYPE causal_twin_build_info gauge\ncausal_twin_build_info{fastdds=\""), std::string::npos)
      << text;
  EXPECT_NE(text.find(",version=\"" CAUSAL_TWIN_VERSION "\"} 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# TYPE process_cpu_seconds_total counter\n"), std::string::npos) << text;
  EXPECT_GT(sample_value(text, "process_resident_memory_bytes"), 1e6);  // this test binary: several MB
  EXPECT_GE(sample_value(text, "process_virtual_memory_bytes"), sample_value(text, "process_resident_memory_bytes"));
  EXPECT_GE(sample_value(text, "process_open_fds"), 3.0);  // stdin, stdout, stderr at least
  EXPECT_GE(sample_value(text, "process_max_fds"), sample_value(text, "process_open_fds"));
  // Started within the last hour, not in the future (the boot time plus the start ticks, against the clock).
  const double started = sample_value(text, "process_start_time_seconds");
  const double now = static_cast<double>(std::time(nullptr));
  EXPECT_LE(started, now + 1.0);
  EXPECT_GT(started, now - 3600.0);
}

TEST(MetricsRegistry, PromtoolAcceptsTheExposition) {
  if (std::system("command -v promtool > /dev/null 2>&1") != 0) GTEST_SKIP() << "promtool not installed";
  MetricsRegistry r;
  r.counter("dds_samples_written_total", "Samples the DDS writer accepted", {{"topic", "causal_twin/alarm"}}).inc(5);
  r.gauge("outbound_queue_depth", "Messages waiting").set(2);
  auto& h = r.histogram("estimator_processing_seconds", "Time per input", {{"asset_group", "ims2"}},
                        latency_buckets_seconds());
  h.observe(0.0003);
  const std::string file = ::testing::TempDir() + "metrics_" + std::to_string(::getpid()) + ".txt";
  std::ofstream(file) << r.exposition();
  const std::string cmd = "promtool check metrics < " + file + " > " + file + ".out 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream in(file + ".out");
  const std::string out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::remove(file.c_str());
  std::remove((file + ".out").c_str());
  EXPECT_EQ(rc, 0) << out;
  EXPECT_EQ(out, "") << out;  // no lint warnings either
}

TEST(MetricsServer, ServesTheRegistryOnLoopbackAndRefusesABusyPort) {
  MetricsRegistry r;
  r.counter("requests_total", "Requests").inc(2);
  const int port = free_port(SOCK_STREAM);
  MetricsServer server(r, "127.0.0.1", port);
  EXPECT_EQ(server.url(), "http://127.0.0.1:" + std::to_string(port) + "/metrics");
  const std::string reply = http_get(port, "/metrics");
  EXPECT_NE(reply.find("200 OK"), std::string::npos) << reply;
  EXPECT_NE(reply.find("text/plain; version=0.0.4"), std::string::npos) << reply;
  EXPECT_NE(reply.find("causal_twin_requests_total 2\n"), std::string::npos) << reply;
  EXPECT_THROW(MetricsServer(r, "127.0.0.1", port), std::runtime_error);
  EXPECT_TRUE(MetricsServer(r, "127.0.0.1", 0).url().empty());
}

}  // namespace
