// The scale benchmark's end of the pipeline (deploy/bench_scale.sh): reads causal_twin/causal_factors and
// causal_twin/causal_factor_sets (a set unpacked into its batches, in order) like the recommender does
// (causal_factors_reader profile) and counts the FRAMES covered, i.e. distinct
// (asset group, sample index) pairs of sample-level Kalman-filter messages, so it counts the same whether the
// estimator sends one message per outcome or one batched message per frame. With sensor-sim
// --wall-clock-stamps a frame's first_sample_time_ns is the wall-clock time it was due, so
//   latency(frame) = arrival of its first factor message - (time_ns - (sample_index mod N) / sample_rate)
// i.e. from when the frame's data was complete at the source to when its factors reached this reader (same
// host clock). Frames before --skip-frames of each group are counted but left out of the latency percentiles
// (the steady state is measured): at start every group fills its calibration window (4096 samples) and tunes
// its noise at once, a one-time stall whose worst latency is printed separately as startup_max_ms.
//   causal_bench_factor_counter --groups K --frames-per-group F [--frame-samples N] [--sample-rate HZ]
//       [--skip-frames S] [--domain D] [--timeout S] [--quiet-exit S] [--qos FILE] [--transport FILE]
//       [--latency-csv FILE]
// --latency-csv: one row per frame (group, frame, arrival_s since the first due time, latency_ms), to see when a
// probe's slow frames came (start-up backlog or steady state).
// Prints "ready" once its reader exists, then one line
//   factors: frames=D expected=E seconds=S frames_per_s=T p50_ms=A p99_ms=B max_ms=C latency_frames=L
//            startup_max_ms=M
// (seconds: from the first frame's due time to the last arrival). Exit code 0 when D == E exactly, 1 otherwise.
// Ends when every frame is covered, after --quiet-exit s without a new frame once some came, or at --timeout.
#include "causal/dds/event_loop.hpp"
#include "causal/dds/factor_sets.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

long long wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

double percentile(std::vector<double>& v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

}  // namespace

int main(int argc, char** argv) {
  long groups = 1, frames_per_group = 1, frame_samples = 1024, skip_frames = 8;
  double sample_rate = 20480.0, timeout_s = 120.0, quiet_exit_s = 5.0;
  int domain = 231;
  std::string qos = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/qos.xml";
  std::string transport = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/localhost.xml";
  std::string latency_csv;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "%s needs a value (see the file header for the options)\n", a.c_str());
      return 2;
    }
    const char* v = argv[++i];
    if (a == "--groups") groups = std::atol(v);
    else if (a == "--frames-per-group") frames_per_group = std::atol(v);
    else if (a == "--frame-samples") frame_samples = std::atol(v);
    else if (a == "--sample-rate") sample_rate = std::atof(v);
    else if (a == "--skip-frames") skip_frames = std::atol(v);
    else if (a == "--domain") domain = std::atoi(v);
    else if (a == "--timeout") timeout_s = std::atof(v);
    else if (a == "--quiet-exit") quiet_exit_s = std::atof(v);
    else if (a == "--qos") qos = v;
    else if (a == "--transport") transport = v;
    else if (a == "--latency-csv") latency_csv = v;
    else {
      std::fprintf(stderr, "unknown option %s (see the file header)\n", a.c_str());
      return 2;
    }
  }
  if (groups < 1 || frames_per_group < 1 || frame_samples < 1 || !(sample_rate > 0)) {
    std::fprintf(stderr, "counts and the sample rate must be positive\n");
    return 2;
  }
  spdlog::set_level(spdlog::level::warn);
  causal::dds::DdsSettings s;
  s.profile_files = {qos, transport};
  s.domain_id = domain;
  s.participant_name = "bench-factor-counter";
  s.security_dir = "off";
  causal::dds::Participant participant(s);
  causal::dds::TypedReader<causal_twin::CausalFactorBatchPubSubType> reader(
      participant, causal::dds::topics::kCausalFactors, causal::dds::profiles::kCausalFactorsReader);
  const auto set_reader = causal::dds::make_factor_set_reader(participant);
  causal::dds::FactorSetCounts sets;
  causal::dds::EventLoop loop;
  loop.attach(reader.get());
  loop.attach(set_reader->get());
  std::printf("ready\n");
  std::fflush(stdout);

  const std::size_t expected = static_cast<std::size_t>(groups) * static_cast<std::size_t>(frames_per_group);
  const double ns_per_sample = 1e9 / sample_rate;
  std::set<std::pair<std::string, std::uint64_t>> covered;
  std::vector<double> latency_ms;
  struct Row {
    std::string group;
    long frame;
    long long arrived_ns;
    double ms;
  };
  std::vector<Row> rows;  // --latency-csv
  double startup_max_ms = 0.0;  // the skipped frames' worst latency (calibration and noise tuning at start)
  long long start_ns = std::numeric_limits<long long>::max(), last_ns = 0;
  const auto began = Clock::now();
  auto progress = began;
  while (covered.size() < expected) {
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - began).count() > timeout_s) break;
    if (!covered.empty() && std::chrono::duration<double>(now - progress).count() > quiet_exit_s) break;
    loop.wait(std::chrono::milliseconds(100));
    const auto on_batch = [&](const causal_twin::CausalFactorBatch& f, const auto&) {
      if (f.time_scale() != causal_twin::SAMPLE_LEVEL || f.kind() != causal_twin::FILTER) return;
      if (!covered.emplace(f.asset_group(), f.sample_index()).second) return;  // a frame counted once
      const long long arrived = wall_ns();
      progress = Clock::now();
      last_ns = std::max(last_ns, arrived);
      const auto s_index = static_cast<double>(f.sample_index());
      start_ns = std::min(start_ns, f.time_ns() - static_cast<long long>(s_index * ns_per_sample));
      const auto frame = static_cast<long>(f.sample_index() / static_cast<std::uint64_t>(frame_samples));
      const auto offset = static_cast<double>(f.sample_index() % static_cast<std::uint64_t>(frame_samples));
      const long long due = f.time_ns() - static_cast<long long>(offset * ns_per_sample);
      const double ms = static_cast<double>(arrived - due) / 1e6;
      if (!latency_csv.empty()) rows.push_back({f.asset_group(), frame, arrived, ms});
      if (frame < skip_frames) {
        startup_max_ms = std::max(startup_max_ms, ms);
      } else {
        latency_ms.push_back(ms);
      }
    };
    reader.take_all(on_batch);
    causal::dds::take_factor_sets(set_reader, sets, on_batch, [](const auto& set, const std::string& problem) {
      std::fprintf(stderr, "factor set of '%s' refused: %s\n", set.asset_group().c_str(), problem.c_str());
    });
  }
  const double seconds = covered.empty() ? 0.0 : static_cast<double>(last_ns - start_ns) / 1e9;
  const std::size_t n_latency = latency_ms.size();
  const double p50 = percentile(latency_ms, 0.50), p99 = percentile(latency_ms, 0.99);
  const double max = latency_ms.empty() ? 0.0 : latency_ms.back();
  std::printf("factors: frames=%zu expected=%zu seconds=%.3f frames_per_s=%.0f p50_ms=%.3f p99_ms=%.3f max_ms=%.3f "
              "latency_frames=%zu startup_max_ms=%.3f\n",
              covered.size(), expected, seconds, seconds > 0 ? static_cast<double>(covered.size()) / seconds : 0.0, p50,
              p99, max, n_latency, startup_max_ms);
  std::fflush(stdout);
  if (!latency_csv.empty()) {
    std::ofstream out(latency_csv);
    out << "group,frame,arrival_s,latency_ms\n";
    for (const auto& r : rows)
      out << r.group << ',' << r.frame << ',' << static_cast<double>(r.arrived_ns - start_ns) / 1e9 << ',' << r.ms << '\n';
    if (!out) {
      std::fprintf(stderr, "cannot write %s\n", latency_csv.c_str());
      return 1;
    }
  }
  return covered.size() == expected && sets.refused == 0 ? 0 : 1;
}
