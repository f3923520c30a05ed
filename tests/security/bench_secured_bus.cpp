// What DDS-Security costs: frames per second and one-way latency percentiles of the open bus and the secured
// bus (the shipped governance: discovery and liveliness encrypted, RTPS messages signed, payloads encrypted
// with AES-GCM and signed per writer), measured in one run, loopback profile, one DDS domain, two processes
// (this program re-executes itself as the reader, with the estimator's identity; the writer is a sensor).
//   causal_bench_security [--frames N] [--latency-frames M] [--rate HZ] [--domain D] [--pki DIR]
// Frames are IMS-shaped: 4 channels x 1024 samples (32 KiB). Throughput: N frames written as fast as the
// reliable keep-all reader takes them (first to last arrival). Latency: M frames paced at HZ, send time in
// first_sample_time_ns, arrival - send per frame (same host clock). Exit code 0 when every frame arrived
// (received == sent, exactly), 1 otherwise, 2 bad usage. Bounded: each phase gives up after 120 s.
#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/security.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <thread>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Options {
  std::size_t frames = 3000, latency_frames = 1000;
  double rate = 500.0;
  int domain = 222;
  std::string pki;
  std::string role = "main";  // main, reader
  std::string security = "off";
};

long long now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);  // the same clock in both processes
  return static_cast<long long>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

causal::dds::DdsSettings settings(const Options& o, const std::string& name, const std::string& identity) {
  causal::dds::DdsSettings s;
  s.profile_files = {std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/qos.xml",
                     std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml"};
  s.domain_id = o.domain;
  s.participant_name = name;
  s.security_dir = o.security;
  s.security_identity = identity;
  return s;
}

// Reader process: takes frames until all N + M arrived (or 120 s without progress), prints one line
// "received=R throughput_fps=F p50_us=A p99_us=B".
int run_reader(const Options& o) {
  causal::dds::Participant participant(settings(o, "bench-reader", "estimator"));
  causal::dds::TypedReader<causal_twin::VibrationFramePubSubType> reader(
      participant, causal::dds::topics::kVibrationFrame, causal::dds::profiles::kVibrationFrameReader);
  causal::dds::EventLoop loop;
  loop.attach(reader.get());
  std::printf("ready\n");
  std::fflush(stdout);
  std::size_t received = 0, throughput_received = 0;
  Clock::time_point first{}, last{};
  std::vector<double> latency_us;
  auto progress = Clock::now();
  const std::size_t expected = o.frames + o.latency_frames;
  while (received < expected && Clock::now() - progress < std::chrono::seconds(120)) {
    loop.wait(std::chrono::milliseconds(100));
    reader.take_all([&](const causal_twin::VibrationFrame& f, const auto&) {
      const auto t = Clock::now();
      ++received;
      progress = t;
      if (f.snapshot_index() == 0) {
        if (throughput_received++ == 0) first = t;
        last = t;
      } else {
        latency_us.push_back(static_cast<double>(now_ns() - f.first_sample_time_ns()) / 1e3);
      }
    });
  }
  const double seconds = std::chrono::duration<double>(last - first).count();
  std::sort(latency_us.begin(), latency_us.end());
  auto pct = [&](double p) {
    return latency_us.empty() ? 0.0 : latency_us[std::min(latency_us.size() - 1, static_cast<std::size_t>(p * static_cast<double>(latency_us.size())))];
  };
  std::printf("received=%zu throughput_fps=%.0f p50_us=%.0f p99_us=%.0f\n", received,
              seconds > 0 ? static_cast<double>(throughput_received - 1) / seconds : 0.0, pct(0.50), pct(0.99));
  return received == expected ? 0 : 1;
}

struct Result {
  bool ok = false;
  std::size_t sent = 0, received = 0;
  double fps = 0, p50 = 0, p99 = 0;
};

// Starts the reader process, writes, and collects the reader's line.
Result run_mode(const Options& o, const std::string& self) {
  int out[2];
  if (pipe(out) != 0) return {};
  const std::vector<std::string> args = {self, "--role", "reader", "--frames", std::to_string(o.frames),
                                         "--latency-frames", std::to_string(o.latency_frames), "--domain",
                                         std::to_string(o.domain), "--security", o.security};
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(out[1], STDOUT_FILENO);
    close(out[0]);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(self.c_str(), argv.data());
    _exit(127);
  }
  close(out[1]);
  FILE* from_reader = fdopen(out[0], "r");
  char line[256] = {0};
  Result r;
  // The reader's lines: anything it logs, then "ready", later "received=...".
  auto next_line_starting = [&](const char* prefix) {
    while (from_reader != nullptr && std::fgets(line, sizeof line, from_reader) != nullptr) {
      if (std::string(line).rfind(prefix, 0) == 0) return true;
    }
    return false;
  };
  if (!next_line_starting("ready")) {
    waitpid(pid, nullptr, 0);
    return r;
  }
  {
    causal::dds::Participant participant(settings(o, "bench-writer", "sensor"));
    causal::dds::TypedWriter<causal_twin::VibrationFramePubSubType> writer(
        participant, causal::dds::topics::kVibrationFrame, causal::dds::profiles::kVibrationFrameWriter);
    const std::atomic<bool> never{false};
    if (writer.wait_for_readers(1, std::chrono::seconds(30), never)) {
      causal_twin::VibrationFrame f;
      f.asset_group("bench");
      f.sample_rate_hz(20480.0);
      f.channel_names({"b1", "b2", "b3", "b4"});
      f.samples_per_channel(1024);
      f.samples(std::vector<double>(4096, 0.25));
      std::uint64_t seq = 0;
      auto send = [&](std::uint64_t phase) {
        f.sequence_number(seq);
        f.first_sample_index(seq * 1024);
        f.snapshot_index(phase);
        f.first_sample_time_ns(now_ns());
        ++seq;
        if (writer.write(f, never, std::chrono::seconds(120)) == causal::dds::WriteResult::Ok) ++r.sent;
      };
      for (std::size_t i = 0; i < o.frames; ++i) send(0);
      writer.wait_for_acknowledgments(std::chrono::seconds(120));
      const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o.rate));
      auto next = Clock::now();
      for (std::size_t i = 0; i < o.latency_frames; ++i) {
        next += period;
        std::this_thread::sleep_until(next);
        send(1);
      }
      writer.wait_for_acknowledgments(std::chrono::seconds(120));
    }
  }
  if (next_line_starting("received=")) {
    std::sscanf(line, "received=%zu throughput_fps=%lf p50_us=%lf p99_us=%lf", &r.received, &r.fps, &r.p50, &r.p99);
  }
  fclose(from_reader);
  int status = 0;
  waitpid(pid, &status, 0);
  r.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && r.sent == o.frames + o.latency_frames &&
         r.received == r.sent;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--frames" && has_value) o.frames = std::stoul(argv[++i]);
    else if (a == "--latency-frames" && has_value) o.latency_frames = std::stoul(argv[++i]);
    else if (a == "--rate" && has_value) o.rate = std::stod(argv[++i]);
    else if (a == "--domain" && has_value) o.domain = std::stoi(argv[++i]);
    else if (a == "--pki" && has_value) o.pki = argv[++i];
    else if (a == "--role" && has_value) o.role = argv[++i];
    else if (a == "--security" && has_value) o.security = argv[++i];
    else {
      std::fprintf(stderr, "usage: %s [--frames N] [--latency-frames M] [--rate HZ] [--domain D] [--pki DIR]\n", argv[0]);
      return 2;
    }
  }
  if (o.frames < 2 || o.latency_frames < 1 || o.rate <= 0) {
    std::fprintf(stderr, "--frames >= 2, --latency-frames >= 1, --rate > 0\n");
    return 2;
  }
  spdlog::set_level(spdlog::level::warn);  // the participants' info lines would clutter the figures
  if (o.role == "reader") return run_reader(o);

  std::string made;
  if (o.pki.empty()) {
    made = (fs::temp_directory_path() / ("causal_bench_pki_" + std::to_string(getpid()))).string();
    fs::remove_all(made);
    const std::string cmd = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/security/make-pki.sh '" + made + "' > /dev/null";
    if (std::system(cmd.c_str()) != 0) {
      std::fprintf(stderr, "cannot make a PKI with %s\n", cmd.c_str());
      return 1;
    }
    o.pki = made;
  }
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  std::printf("security bench: 4 x 1024-sample frames (32 KiB), loopback profile, domain %d; throughput %zu frames, "
              "latency %zu frames at %.0f/s\n", o.domain, o.frames, o.latency_frames, o.rate);
  Result results[2];
  for (int secured = 0; secured < 2; ++secured) {
    o.security = secured ? o.pki : causal::dds::kSecurityOff;
    results[secured] = run_mode(o, self);
    const Result& r = results[secured];
    std::printf("%-8s sent=%zu received=%zu  throughput %.0f frames/s (%.1f MB/s)  latency p50 %.0f us  p99 %.0f us%s\n",
                secured ? "secured" : "open", r.sent, r.received, r.fps, r.fps * 32768.0 / 1e6, r.p50, r.p99,
                r.ok ? "" : "  INCOMPLETE");
    std::fflush(stdout);
  }
  if (results[0].fps > 0 && results[1].fps > 0) {
    std::printf("secured/open: throughput x%.2f, p50 latency x%.2f, p99 latency x%.2f\n", results[1].fps / results[0].fps,
                results[0].p50 > 0 ? results[1].p50 / results[0].p50 : 0.0,
                results[0].p99 > 0 ? results[1].p99 / results[0].p99 : 0.0);
  }
  if (!made.empty()) fs::remove_all(made);
  return results[0].ok && results[1].ok ? 0 : 1;
}
