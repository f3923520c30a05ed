// Raw Fast DDS throughput for the pipeline's own frames: the reference the scale benchmark
// (deploy/bench_scale.sh) divides the pipeline's throughput by. No estimation: one writer, one reader, the
// same VibrationFrame type, the same frame size (G channels x N samples), the same asset-group instances
// (round-robin, as sensor-sim publishes them), the same QoS profiles (vibration_frame_writer/_reader) and
// transport file as the pipeline's frame topic.
//   causal_bench_raw_dds [--groups K] [--frames-per-group F] [--channels G] [--frame-samples N] [--domain D]
//                        [--qos FILE] [--transport FILE]
// The process forks before any DDS entity exists: the child is the reader, the parent the writer (two
// processes, like sensor-sim and causal-estimator). The writer stamps its wall-clock start in every frame's
// first_sample_time_ns; the reader measures from there to the last arrival and prints one line
//   raw_dds: received=R expected=E seconds=S frames_per_s=T
// Exit code 0 when every frame arrived (received == expected, exactly), 1 otherwise, 2 bad usage. Bounded:
// the reader gives up after 60 s without progress.
#include "causal/dds/event_loop.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "bench_dds_settings.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  int groups = 16, channels = 4, frame_samples = 1024, domain = 230;
  long frames_per_group = 250;
  std::string qos = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/qos.xml";
  std::string transport = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml";
};

long long wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int run_reader(const Options& o, std::size_t expected) {
  causal::dds::Participant participant(causal::bench::dds_settings(o, "bench-raw-reader"));
  causal::dds::TypedReader<causal_twin::VibrationFramePubSubType> reader(
      participant, causal::dds::topics::kVibrationFrame, causal::dds::profiles::kVibrationFrameReader);
  causal::dds::EventLoop loop;
  loop.attach(reader.get());
  std::size_t received = 0;
  long long start_ns = 0, last_ns = 0;
  auto progress = Clock::now();
  while (received < expected && Clock::now() - progress < std::chrono::seconds(60)) {
    loop.wait(std::chrono::milliseconds(100));
    reader.take_all([&](const causal_twin::VibrationFrame& f, const auto&) {
      ++received;
      last_ns = wall_ns();
      start_ns = f.first_sample_time_ns();
      progress = Clock::now();
    });
  }
  const double seconds = static_cast<double>(last_ns - start_ns) / 1e9;
  std::printf("raw_dds: received=%zu expected=%zu seconds=%.3f frames_per_s=%.0f\n", received, expected, seconds,
              seconds > 0 ? static_cast<double>(received) / seconds : 0.0);
  std::fflush(stdout);
  return received == expected ? 0 : 1;
}

int run_writer(const Options& o) {
  causal::dds::Participant participant(causal::bench::dds_settings(o, "bench-raw-writer"));
  causal::dds::TypedWriter<causal_twin::VibrationFramePubSubType> writer(
      participant, causal::dds::topics::kVibrationFrame, causal::dds::profiles::kVibrationFrameWriter);
  std::atomic<bool> stop{false};
  if (!writer.wait_for_readers(1, std::chrono::seconds(30), stop)) {
    std::fprintf(stderr, "raw_dds: no reader matched within 30 s\n");
    return 1;
  }
  std::vector<causal::dds::FrameHeader> headers(static_cast<std::size_t>(o.groups));
  std::vector<std::string> names;
  for (int c = 1; c <= o.channels; ++c) names.push_back("ch" + std::to_string(c));
  for (int g = 0; g < o.groups; ++g) {
    char id[32];
    std::snprintf(id, sizeof id, "sim-%04d", g);
    auto& h = headers[static_cast<std::size_t>(g)];
    h.asset_group = id;
    h.sample_rate_hz = 20480.0;
    h.channel_names = names;
    h.unit = "g";
    h.source = "bench-raw-dds";
  }
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise;
  Eigen::MatrixXd block(o.frame_samples, o.channels);
  for (Eigen::Index i = 0; i < block.size(); ++i) block.data()[i] = noise(rng);
  causal_twin::VibrationFrame frame;
  const long long start = wall_ns();
  for (long r = 0; r < o.frames_per_group; ++r) {
    for (auto& h : headers) {
      h.discontinuity = r == 0;
      h.first_sample_time_ns = start;  // the reader measures from the writer's start
      causal::dds::to_frame(h, block, 0, o.frame_samples, frame);
      if (writer.write(frame, stop, std::chrono::seconds(30)) != causal::dds::WriteResult::Ok) {
        std::fprintf(stderr, "raw_dds: a frame was not accepted within 30 s\n");
        return 1;
      }
      ++h.sequence;
      h.first_sample_index += static_cast<std::uint64_t>(o.frame_samples);
    }
  }
  writer.wait_for_acknowledgments(std::chrono::seconds(30));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--groups") o.groups = std::atoi(value().c_str());
    else if (a == "--frames-per-group") o.frames_per_group = std::atol(value().c_str());
    else if (a == "--channels") o.channels = std::atoi(value().c_str());
    else if (a == "--frame-samples") o.frame_samples = std::atoi(value().c_str());
    else if (a == "--domain") o.domain = std::atoi(value().c_str());
    else if (a == "--qos") o.qos = value();
    else if (a == "--transport") o.transport = value();
    else {
      std::fprintf(stderr, "usage: %s [--groups K] [--frames-per-group F] [--channels G] [--frame-samples N] "
                           "[--domain D] [--qos FILE] [--transport FILE]\n", argv[0]);
      return 2;
    }
  }
  if (o.groups < 1 || o.frames_per_group < 1 || o.channels < 1 || o.frame_samples < 1) {
    std::fprintf(stderr, "every count must be >= 1\n");
    return 2;
  }
  spdlog::set_level(spdlog::level::warn);
  const std::size_t expected = static_cast<std::size_t>(o.groups) * static_cast<std::size_t>(o.frames_per_group);
  const pid_t reader = fork();  // before any DDS entity: the child starts clean
  if (reader < 0) return 1;
  if (reader == 0) _exit(run_reader(o, expected));
  const int wrote = run_writer(o);
  int status = 0;
  waitpid(reader, &status, 0);
  return wrote == 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : 1;
}
