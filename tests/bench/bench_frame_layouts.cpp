// What each candidate frame layout costs on one host, measured the same way for all (tests/bench/frame_layouts.idl):
//   double           the product's VibrationFrame: 64-bit samples, unbounded, keyed by asset group; one host's
//                    shared-memory transport copies each frame into the reader's payload pool and the reader
//                    decodes it once for its key
//   float32          the same with 32-bit samples (half the bytes; 24-bit mantissa)
//   bounded(-float32) every string and sequence bounded, still keyed: Fast DDS 2.9 refuses data sharing for keyed
//                    types, so this isolates what bounding alone does
//   shared(-float32) bounded and unkeyed, written with a PREALLOCATED history: Fast DDS's default data_sharing
//                    AUTOMATIC engages (the writer checks it, the run fails otherwise); no DDS-Security possible
// One writer process, one reader process (forked before any DDS entity), the same groups (round-robin like
// sensor-sim), frame size, QoS (tests/bench/frame_layouts_qos.xml) and transport file. The writer converts an
// N x G double block into the frame (as the sources do), the reader converts each frame back into an N x G double
// block (as the estimator does, narrowing and widening included). Each process's user+system CPU over its transfer
// (getrusage, start-up excluded) is divided by the frames; the layouts run in turn, --rounds times, interleaved.
//   causal_bench_frame_layouts [--layouts double,float32,bounded,bounded-float32,shared,shared-float32]
//                              [--rounds R] [--groups K] [--frames-per-group F] [--channels G] [--frame-samples N]
//                              [--domain D] [--qos FILE] [--transport FILE]
// One line per layout and round:
//   frame_layout: layout=L round=r received=R expected=E frames_per_s=T writer_cpu_us=W reader_cpu_us=C max_abs_error=X
// (max_abs_error: the largest |received - sent| sample of the first frames, 0 for 64-bit layouts). The reader gives
// up after 15 s without a frame. Exit 0 when every frame of every run arrived (received == expected, exactly), 1
// otherwise, 2 bad usage.
#include "bench_dds_settings.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal/dds/event_loop.hpp"
#include "causal_twinPubSubTypes.h"
#include "frame_layoutsPubSubTypes.h"
#include "causal/dds/sample_limits.hpp"

#include <Eigen/Dense>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

// The receive-side limit check every product topic gets (causal::dds::GuardedPubSubType calls check_limits): the
// same checks as for VibrationFrame (sample_limits.cpp: the key and the channel names), so every layout pays them.
namespace causal_twin_bench {
template <typename Frame>
causal::dds::Refusal frame_limits(const Frame& s, std::string& why) {
  if (s.asset_group().size() > causal::dds::kMaxIdBytes) {
    why = "asset_group too long";
    return causal::dds::Refusal::KeyTooLong;
  }
  if (s.channel_names().size() > causal::dds::kMaxChannels) {
    why = "too many channel names";
    return causal::dds::Refusal::Malformed;
  }
  return causal::dds::Refusal::None;
}
causal::dds::Refusal check_limits(const VibrationFrameF32& s, std::string& why) { return frame_limits(s, why); }
causal::dds::Refusal check_limits(const BoundedVibrationFrame& s, std::string& why) { return frame_limits(s, why); }
causal::dds::Refusal check_limits(const BoundedVibrationFrameF32& s, std::string& why) { return frame_limits(s, why); }
causal::dds::Refusal check_limits(const SharedVibrationFrame& s, std::string& why) { return frame_limits(s, why); }
causal::dds::Refusal check_limits(const SharedVibrationFrameF32& s, std::string& why) { return frame_limits(s, why); }
}  // namespace causal_twin_bench

namespace {

using Clock = std::chrono::steady_clock;
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct Options {
  std::vector<std::string> layouts{"double", "float32", "bounded", "shared", "shared-float32"};
  int rounds = 3, groups = 16, channels = 4, frame_samples = 1024, domain = 230;
  long frames_per_group = 250;
  std::string qos = std::string(CAUSAL_TWIN_BENCH_DIR) + "/frame_layouts_qos.xml";
  std::string transport = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml";
};

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

// A data-sharing writer maps its history into /dev/shm/fast_datasharing_* (Fast DDS 2.9's DataSharingPayloadPool);
// without one, the layout runs over the transport. Run under tests/support/isolate.sh (a private /dev/shm).
bool data_sharing_segment() {
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/dev/shm", ec)) {
    if (e.path().filename().string().rfind("fast_datasharing", 0) == 0) return true;
  }
  return false;
}

// Fills a frame of any layout from rows of a double block (sample-major), as to_frame does for VibrationFrame.
template <typename Frame>
void fill(Frame& f, const std::string& group, std::uint64_t seq, const std::vector<std::string>& names,
          const Eigen::MatrixXd& block) {
  f.asset_group(group);
  f.sequence_number(seq);
  f.first_sample_index(seq * static_cast<std::uint64_t>(block.rows()));
  f.snapshot_index(0);
  f.first_sample_time_ns(1'700'000'000'000'000'000LL);
  f.sample_rate_hz(20480.0);
  auto& channel_names = f.channel_names();
  channel_names.clear();
  for (const auto& n : names) channel_names.emplace_back(n);
  f.unit("g");
  f.samples_per_channel(static_cast<std::uint32_t>(block.rows()));
  f.discontinuity(seq == 0);
  f.end_of_segment(false);
  f.source("bench-frame-layouts");
  auto& out = f.samples();
  using Scalar = typename std::decay_t<decltype(out)>::value_type;
  out.resize(static_cast<std::size_t>(block.size()));
  Eigen::Map<Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(out.data(), block.rows(),
                                                                                     block.cols()) =
      block.template cast<Scalar>();
}

// The reader's side: the frame's samples into an N x G double block (the estimator's input).
template <typename Frame>
void unpack(const Frame& f, RowMajor& into) {
  const auto& s = f.samples();
  using Scalar = typename std::decay_t<decltype(s)>::value_type;
  const Eigen::Index g = static_cast<Eigen::Index>(f.channel_names().size());
  const Eigen::Index n = static_cast<Eigen::Index>(f.samples_per_channel());
  into = Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(s.data(), n, g)
             .template cast<double>();
}

Eigen::MatrixXd test_block(const Options& o) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise;
  Eigen::MatrixXd block(o.frame_samples, o.channels);
  for (Eigen::Index i = 0; i < block.size(); ++i) block.data()[i] = noise(rng);
  return block;
}

struct ReaderResult {
  std::size_t received = 0;
  double seconds = 0, cpu_s = 0, max_abs_error = 0;
};

template <typename PubSub>
ReaderResult run_reader(const Options& o, const std::string& topic, std::size_t expected) {
  causal::dds::Participant participant(causal::bench::dds_settings(o, "bench-layout-reader"));
  causal::dds::TypedReader<PubSub> reader(participant, topic, "frame_layout_reader");
  causal::dds::EventLoop loop;
  loop.attach(reader.get());
  const Eigen::MatrixXd sent = test_block(o);
  ReaderResult r;
  RowMajor block;
  double cpu0 = -1;
  Clock::time_point first{}, last{};
  auto progress = Clock::now();
  while (r.received < expected && Clock::now() - progress < std::chrono::seconds(15)) {
    loop.wait(std::chrono::milliseconds(100));
    reader.take_all([&](const typename PubSub::type& f, const auto&) {
      if (cpu0 < 0) {
        cpu0 = cpu_seconds();
        first = Clock::now();
      }
      unpack(f, block);
      if (f.sequence_number() == 0 && block.rows() == sent.rows() && block.cols() == sent.cols()) {
        r.max_abs_error = std::max(r.max_abs_error, (block - sent).cwiseAbs().maxCoeff());
      }
      ++r.received;
      last = progress = Clock::now();
    });
  }
  r.cpu_s = cpu0 < 0 ? 0 : cpu_seconds() - cpu0;
  r.seconds = std::chrono::duration<double>(last - first).count();
  return r;
}

template <typename PubSub>
int run_writer(const Options& o, const std::string& topic, const std::string& profile, int result_fd) {
  causal::dds::Participant participant(causal::bench::dds_settings(o, "bench-layout-writer"));
  causal::dds::TypedWriter<PubSub> writer(participant, topic, profile);
  const bool sharing = data_sharing_segment();
  if (sharing != (profile == "frame_layout_shared_writer")) {
    std::fprintf(stderr, "frame_layouts: %s data sharing where it was %s\n", sharing ? "uses" : "does not use",
                 sharing ? "not expected" : "expected");
    return 1;
  }
  std::atomic<bool> stop{false};
  if (!writer.wait_for_readers(1, std::chrono::seconds(30), stop)) {
    std::fprintf(stderr, "frame_layouts: no reader matched within 30 s\n");
    return 1;
  }
  std::vector<std::string> names;
  for (int c = 1; c <= o.channels; ++c) names.push_back("ch" + std::to_string(c));
  std::vector<std::string> groups;
  for (int g = 0; g < o.groups; ++g) groups.push_back("sim-" + std::to_string(1000 + g));
  const Eigen::MatrixXd block = test_block(o);
  typename PubSub::type frame;
  const double cpu0 = cpu_seconds();
  for (long r = 0; r < o.frames_per_group; ++r) {
    for (const auto& g : groups) {
      fill(frame, g, static_cast<std::uint64_t>(r), names, block);
      if (writer.write(frame, stop, std::chrono::seconds(30)) != causal::dds::WriteResult::Ok) {
        std::fprintf(stderr, "frame_layouts: a frame was not accepted within 30 s\n");
        return 1;
      }
    }
  }
  const double cpu = cpu_seconds() - cpu0;
  writer.wait_for_acknowledgments(std::chrono::seconds(30));
  if (write(result_fd, &cpu, sizeof cpu) != static_cast<ssize_t>(sizeof cpu)) return 1;
  return 0;
}

// One layout, one round: the writer in a child process, the reader here (in a second child), each starting clean.
template <typename PubSub>
bool run_layout(const Options& o, const std::string& layout, int round, const std::string& profile) {
  const std::size_t expected = static_cast<std::size_t>(o.groups) * static_cast<std::size_t>(o.frames_per_group);
  const std::string topic = "bench/frame_layout_" + layout;
  int fds[2];
  if (pipe(fds) != 0) return false;
  const pid_t writer = fork();
  if (writer < 0) return false;
  if (writer == 0) {
    close(fds[0]);
    _exit(run_writer<PubSub>(o, topic, profile, fds[1]));
  }
  close(fds[1]);
  int rfds[2];
  if (pipe(rfds) != 0) return false;
  const pid_t reader = fork();
  if (reader == 0) {
    close(rfds[0]);
    const ReaderResult r = run_reader<PubSub>(o, topic, expected);
    _exit(write(rfds[1], &r, sizeof r) == static_cast<ssize_t>(sizeof r) ? 0 : 1);
  }
  close(rfds[1]);
  ReaderResult r;
  double writer_cpu = 0;
  const bool got_reader = read(rfds[0], &r, sizeof r) == static_cast<ssize_t>(sizeof r);
  const bool got_writer = read(fds[0], &writer_cpu, sizeof writer_cpu) == static_cast<ssize_t>(sizeof writer_cpu);
  close(rfds[0]);
  close(fds[0]);
  int ws = 0, rs = 0;
  waitpid(writer, &ws, 0);
  waitpid(reader, &rs, 0);
  const double n = static_cast<double>(expected);
  std::printf("frame_layout: layout=%s round=%d received=%zu expected=%zu frames_per_s=%.0f writer_cpu_us=%.1f "
              "reader_cpu_us=%.1f max_abs_error=%.3g\n",
              layout.c_str(), round, r.received, expected, r.seconds > 0 ? static_cast<double>(r.received) / r.seconds : 0.0,
              writer_cpu * 1e6 / n, r.cpu_s * 1e6 / n, r.max_abs_error);
  std::fflush(stdout);
  return got_reader && got_writer && r.received == expected && WIFEXITED(ws) && WEXITSTATUS(ws) == 0;
}

const std::vector<std::string> kLayouts{"double", "float32", "bounded", "bounded-float32", "shared", "shared-float32"};

bool run_named(const Options& o, const std::string& layout, int round) {
  namespace b = causal_twin_bench;
  const std::string plain = "frame_layout_writer", shared = "frame_layout_shared_writer";
  if (layout == "double") return run_layout<causal_twin::VibrationFramePubSubType>(o, layout, round, plain);
  if (layout == "float32") return run_layout<b::VibrationFrameF32PubSubType>(o, layout, round, plain);
  if (layout == "bounded") return run_layout<b::BoundedVibrationFramePubSubType>(o, layout, round, plain);
  if (layout == "bounded-float32") return run_layout<b::BoundedVibrationFrameF32PubSubType>(o, layout, round, plain);
  if (layout == "shared") return run_layout<b::SharedVibrationFramePubSubType>(o, layout, round, shared);
  return run_layout<b::SharedVibrationFrameF32PubSubType>(o, layout, round, shared);
}

[[noreturn]] void usage(const char* argv0, int code = 2) {
  std::fprintf(code == 0 ? stdout : stderr, "usage: %s [--layouts double,float32,bounded,bounded-float32,shared,shared-float32] "
                       "[--rounds R] [--groups K] "
                       "[--frames-per-group F] [--channels G] [--frame-samples N] [--domain D] [--qos FILE] "
                       "[--transport FILE]\n", argv0);
  std::exit(code);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") usage(argv[0], 0);
    if (i + 1 >= argc) {
      std::fprintf(stderr, "%s needs a value\n", a.c_str());
      usage(argv[0]);
    }
    const std::string v = argv[++i];
    if (a == "--layouts") {
      o.layouts.clear();
      std::stringstream ss(v);
      for (std::string item; std::getline(ss, item, ',');) {
        if (std::find(kLayouts.begin(), kLayouts.end(), item) == kLayouts.end()) {
          std::fprintf(stderr, "--layouts: unknown layout '%s'\n", item.c_str());
          std::exit(2);
        }
        o.layouts.push_back(item);
      }
    } else if (a == "--rounds") o.rounds = std::atoi(v.c_str());
    else if (a == "--groups") o.groups = std::atoi(v.c_str());
    else if (a == "--frames-per-group") o.frames_per_group = std::atol(v.c_str());
    else if (a == "--channels") o.channels = std::atoi(v.c_str());
    else if (a == "--frame-samples") o.frame_samples = std::atoi(v.c_str());
    else if (a == "--domain") o.domain = std::atoi(v.c_str());
    else if (a == "--qos") o.qos = v;
    else if (a == "--transport") o.transport = v;
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      usage(argv[0]);
    }
  }
  if (o.rounds < 1 || o.groups < 1 || o.groups > 16 || o.frames_per_group < 1 || o.channels < 1 ||
      o.channels > 64 || o.frame_samples < 1 || o.channels * o.frame_samples > 8192 || o.layouts.empty()) {
    std::fprintf(stderr, "counts must be >= 1, groups <= 16 (the QoS file's max_instances), channels <= 64, channels x frame samples <= 8192 "
                         "(the bounded layouts' bound)\n");
    std::exit(2);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  spdlog::set_level(spdlog::level::warn);
  bool all = true;
  for (int round = 1; round <= o.rounds; ++round) {
    for (const auto& layout : o.layouts) all = run_named(o, layout, round) && all;
  }
  return all ? 0 : 1;
}
