#include "sim_options.hpp"

#include <CLI/CLI.hpp>

namespace causal::sim {

std::optional<SimOptions> parse_sim_options(int argc, char** argv, int& exit_code) {
  SimOptions o;
  CLI::App app{
      "sensor-sim: publishes simulated vibration frames on DDS for many asset groups at once (load and fault\n"
      "tests). Each group is a stable structural VAR with known causal factors, drawn from --seed and the group's\n"
      "index: the same seed gives the same factors and samples. Frames go round-robin over the groups, each\n"
      "group with gap-free sequence numbers and sample times derived from the sample index (not the clock); the\n"
      "first frame of every group is flagged as a discontinuity; end_of_segment is never set (a continuous sensor).\n"
      "It stops at --frames-per-group, --max-runtime or SIGINT/SIGTERM, whichever comes first; after a normal end\n"
      "it waits up to 30 s (after a stop 2 s, never past --max-runtime) for the readers to acknowledge every frame.\n"
      "At exit it prints one line\n"
      "  sensor-sim: sent frames=<total> groups=<N> per_group=<frames every group got> lost=<failed writes>\n"
      "Exit codes: 0 done or stopped, 1 DDS or internal error, 2 bad arguments, 3 no reader matched in time,\n"
      "4 frames lost (a write failed or was not accepted within --write-timeout).\n"
      "With --plant it simulates condition-level plants instead (one condition vector per group and snapshot on\n"
      "causal_twin/condition_input) and obeys approved interventions from causal_twin/intervention: each is applied\n"
      "from its start snapshot index to its group's true structural model (the do-operation the twin's what-if\n"
      "assumes). It then prints\n"
      "  sensor-sim: sent snapshots=<n> groups=<N> lost=<n> interventions applied=<n> refused=<n> other_groups=<n>\n"
      "and exits 4 when an intervention was refused (its start snapshot already published, bad channel or size)\n"
      "or a snapshot was lost."};
  dds::add_common_options(app, o.dds);
  app.add_option("--groups", o.groups, "number of simulated asset groups")->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--group-prefix", o.group_prefix, "asset-group ids are this prefix and the group index, at least 4 digits (sim-0000, sim-0001, ...)")
      ->capture_default_str();
  app.add_option("--channels", o.channels, "channels per asset group (G)")->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--lag-order", o.lag_order, "lag order M of the simulated structural VAR")->check(CLI::Range(1, 8))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the factors and the noise")->capture_default_str();
  app.add_option("--rate", o.rate_hz,
                 "samples per second per group, wall clock (pacing); 0 = as fast as the readers take them. "
                 "--rate equal to --sample-rate is real time")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--sample-rate", o.sample_rate_hz,
                 "sampling rate stamped in the frames, Hz; sample i of a group is at --start-time-ns + i / sample-rate")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--start-time-ns", o.start_time_ns, "time of sample 0, ns since the Unix epoch (UTC)")
      ->capture_default_str();
  app.add_flag("--wall-clock-stamps", o.wall_clock_stamps,
               "stamp sample 0 with the wall clock (UTC) when publishing starts, instead of --start-time-ns: paced "
               "at --rate equal to --sample-rate, a frame's first_sample_time_ns is when it is due (latency "
               "benchmarks: deploy/bench_scale.sh)");
  app.add_flag("--stagger", o.stagger,
               "with --rate: spread the groups' frames evenly over each frame period (group g of K due g/K of a "
               "period after group 0, its sample times shifted alike) instead of all at once");
  app.add_option("--frame-samples", o.frame_samples, "samples per channel in one frame")
      ->check(CLI::Range(16, 8192))->capture_default_str();
  app.add_option("--frames-per-group", o.frames_per_group, "stop after this many frames per group (0 = no bound)")
      ->capture_default_str();
  app.add_option("--max-runtime", o.max_runtime_s,
                 "stop after this many seconds in any case, waiting for readers included (0 = no bound)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  dds::add_source_wait_options(app, o.wait, false);
  app.add_option("--write-timeout", o.write_timeout_s,
                 "a frame (with --plant a condition vector) the readers do not accept within this many seconds is counted "
                 "lost (exit 4)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--plant", o.plants,
                 "condition-level plant mode: plant kinds, cycled over the groups: lever (channel 2 drives channel 1, "
                 "whose level rises through it), no-lever (channels 1 and 2 rise on their own), near-unit-root (the "
                 "lever plant with a slow, barely stable lever); e.g. --plant lever,no-lever")
      ->delimiter(',')->check(CLI::IsMember({"lever", "no-lever", "near-unit-root"}));
  app.add_option("--snapshots", o.snapshots, "with --plant: snapshots per group")->check(CLI::Range(1, 10000000))
      ->capture_default_str();
  app.add_option("--snapshot-rate", o.snapshot_rate,
                 "with --plant: snapshots per second per group, wall clock (0 = as fast as the readers take them)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--plant-feature", o.plant_feature, "with --plant: the feature name stamped in the condition vectors")
      ->capture_default_str();
  app.add_option("--snapshot-seconds", o.snapshot_seconds, "with --plant: data time between snapshots, s")
      ->check(CLI::Range(1, 86400))->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    exit_code = app.exit(e);      // prints the help or the error
    if (exit_code != 0) exit_code = 2;  // bad arguments, as documented
    return std::nullopt;
  }
  exit_code = 0;
  return o;
}

}  // namespace causal::sim
