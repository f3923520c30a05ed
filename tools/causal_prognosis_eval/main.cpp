// causal-prognosis-eval: how well the twin's time-to-level prognosis (causal_prognosis, fed exactly as
// alarm-recommender feeds it) predicts when a degrading channel reaches 2x and 4x its baseline and its end of
// life, beside two anchors at the same decision points (prognosis_anchors.hpp). The event is the alarm's own:
// the first snapshot from the first alarm on whose trailing 5-snapshot median of the level reaches the
// multiple of the baseline the engine had at the first alarm (one spike is not "reached"); a level never
// reached before the stop is scored at the stop. Two sources:
//   --ims FILE      IMS-format feature table (tests/bench/prognosis_eval.sh uses test 2): the services' chain
//                   (causal_alarms_pipeline) gives the observations; --stop-index (default 981, the last running
//                   snapshot of test 2).
//   --sim           simulated run-to-failure channels (run_to_failure_sim.hpp), --seeds N per noise kind
//                   (Gaussian and uniform) from --first-seed.
// Prints one table per source: per level and method, decision points, share answered, coverage of the 90 %
// intervals (answered ones), median width over the actual remaining time, alpha-lambda at +-20 % / +-30 %.
#include "causal/config/exit_codes.hpp"
#include "prognosis_scoring.hpp"
#include "run_to_failure_sim.hpp"

#include "causal/advice/recommender_params.hpp"
#include "causal/alarms/alarm_pipeline.hpp"
#include "causal/config/config_search.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <string>

using namespace causal;
using namespace causal::prognosis_eval;

namespace {

causal::config::ConfigChoice alarms_choice() {
  return causal::config::find_config_file("alarms.yaml", "", causal::config::ConfigKind::Parameters);
}

struct Options {
  std::string ims;
  std::string feature_name;
  int channel = 1;
  std::uint64_t stop_index = 981;
  bool sim = false;
  int seeds = 20;
  int first_seed = 1;  // seeds first_seed .. first_seed + seeds - 1 (other seeds: a held-out judge)
  bool episodic = false;  // simulated wear in episodes (run_to_failure_sim.hpp)
  bool trace = false;
  std::string alarms_config;     // alarm-recommender's alarms.yaml, read by its own loader
  alarms::AlarmParams alarm;     // its condition_level section: the engine whose alarms start the prognosis
  prognosis::PrognosisParams params;  // its prognosis section, with the options below applied over it
};

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "causal-prognosis-eval: " << why << "\n"
            << "usage: causal-prognosis-eval (--ims FILE [--feature-name NAME] [--channel 1] [--stop-index 981] | "
               "--sim [--seeds 20] [--episodic]) [--alarms-config FILE] [--acceleration-diffusion Q] [--forecast-diffusion F] [--first-seed 1] [--min-trend-z Z] [--pessimistic-z Z] [--calibration-lag H] [--calibration-memory N] [--huber-k K] [--end-of-life-ratio R] [--trend-fit-limit L] [--no-power-law] [--no-fill] [--trace]\n";
  std::exit(causal::config::kExitUsage);
}

void print_help() {
  std::cout << "causal-prognosis-eval: how well the time-to-level prognosis predicts when a degrading channel reaches 2x,\n"
               "4x its baseline and its end of life (trailing 5-snapshot median at the multiple of the baseline;\n"
               "the stop when never reached), beside a log-linear Theil-Sen trend with bootstrap intervals and a\n"
               "random walk with drift (inverse-Gaussian first passage), at every snapshot from the first alarm on; the\n"
               "row long-run is the twin's long-run model alone (Wiener process on the log of the log excess); the row\n"
               "conformal: the empirical errors of the channel's own mean-rate level forecasts at each horizon.\n"
               "Columns: share answered, coverage of the 90 % intervals (answered ones), median interval width over\n"
               "the actual remaining time, alpha-lambda (share of decision points whose median is within +-20 % /\n"
               "+-30 % of the actual remaining time; unknown = not within).\n"
               "usage: causal-prognosis-eval (--ims FILE [--feature-name NAME] [--channel 1] [--stop-index 981] | --sim\n"
               "       [--seeds 20] [--first-seed 1] [--episodic]) [--alarms-config FILE] [--acceleration-diffusion Q] [--forecast-diffusion F]\n"
               "       [--min-trend-z Z] [--pessimistic-z Z] [--calibration-lag H] [--calibration-memory N]\n"
               "       [--huber-k K] [--end-of-life-ratio R] [--trend-fit-limit L] [--no-power-law] [--no-fill] [--trace]\n"
               "  (every tuning option overrides the prognosis parameters of the alarms file; see docs/prognosis.md)\n"
               "  --alarms-config FILE  alarm-recommender's parameter file (condition_level and prognosis sections);\n"
               "                     default: " << alarms_choice().describe("alarms.yaml") << "\n"
               "  --ims FILE         IMS-format feature table, run through the services' alarm chain\n"
               "  --sim              simulated run-to-failure channels with known crossing times\n"
               "  --seeds N          seeds per noise kind (Gaussian, uniform) with --sim\n"
               "  --episodic         with --sim: the wear shows in episodes (the level holds 4-24 h, then catches up\n"
               "                     with the smooth path in 1 h)\n"
               "  --trend-fit-limit L  the local trend answers while its forecast inflation is <= L (default 2.51),\n"
               "                     else the long-run model (0: long-run first)\n"
               "  --no-power-law     the long-run model with the exponential-excess shape only\n"
               "  --no-fill          the long-run model does not answer where a fitting local trend says unknown\n"
               "  --trace            one line per decision point and level (with --sim also each run's level series)\n"
               "  --help, --version  this text; the project version\n"
               "Exit: 0 tables printed, 2 bad options or input.\n";
}

// The file the service reads: --alarms-config, else the documented search (config_search.hpp).
Options load_alarms_file(int argc, char** argv) {
  Options o;
  o.alarms_config = alarms_choice().path;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--alarms-config") o.alarms_config = argv[i + 1];
  }
  if (o.alarms_config.empty()) usage(alarms_choice().describe("alarms.yaml") + ": give --alarms-config FILE");
  const advice::RecommenderParams file = advice::load_recommender_params(o.alarms_config);
  o.alarm = file.condition;
  o.params = file.prognosis;
  return o;
}

Options parse(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      print_help();
      std::exit(0);
    }
  }
  Options o = load_alarms_file(argc, argv);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      print_help();
      std::exit(0);
    }
    if (a == "--version") {
      std::cout << CAUSAL_TWIN_VERSION << "\n";
      std::exit(0);
    }
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--alarms-config") value();  // read first (load_alarms_file)
    else if (a == "--ims") o.ims = value();
    else if (a == "--feature-name") o.feature_name = value();
    else if (a == "--channel") o.channel = std::stoi(value());
    else if (a == "--stop-index") o.stop_index = std::stoull(value());
    else if (a == "--sim") o.sim = true;
    else if (a == "--seeds") o.seeds = std::stoi(value());
    else if (a == "--trace") o.trace = true;
    else if (a == "--episodic") o.episodic = true;
    else if (a == "--acceleration-diffusion") o.params.trend.acceleration_diffusion = std::stod(value());
    else if (a == "--forecast-diffusion") o.params.trend.forecast_diffusion = std::stod(value());
    else if (a == "--pessimistic-z") o.params.pessimistic_z = std::stod(value());
    else if (a == "--calibration-lag") o.params.trend.calibration_lag_hours = std::stod(value());
    else if (a == "--calibration-memory") o.params.trend.calibration_memory = std::stod(value());
    else if (a == "--huber-k") o.params.trend.huber_k = std::stod(value());
    else if (a == "--first-seed") o.first_seed = std::stoi(value());
    else if (a == "--no-power-law") o.params.excess.power_law = false;
    else if (a == "--no-fill") o.params.long_run_fills_unknown = false;
    else if (a == "--trend-fit-limit") o.params.trend_fit_limit = std::stod(value());
    else if (a == "--min-trend-z") o.params.min_trend_z = std::stod(value());
    else if (a == "--end-of-life-ratio") o.params.end_of_life_ratio = std::stod(value());
    else usage("unknown option " + a);
  }
  if (o.ims.empty() == !o.sim) usage("give exactly one of --ims FILE and --sim");
  if (o.episodic && !o.sim) usage("--episodic needs --sim");
  o.params.validate();
  return o;
}

void print_trace(const PrognosisScorer& s) {
  for (const auto& line : s.trace) std::cout << "trace " << line << "\n";
}

// With --sim --trace, the wearing channel's level after the run's trace lines, for measurements that need the
// series itself (tests/bench/prognosis_episodes.py): "run SEED KIND FIRST_ALARM BASELINE", then one
// "series INDEX TIME_NS LEVEL" per row.
void print_series(const SimSpec& spec, const SimRun& run, const PrognosisScorer& s) {
  std::printf("run %llu %s %lld %.9g\n", static_cast<unsigned long long>(spec.seed), spec.gaussian ? "gaussian" : "uniform",
              static_cast<long long>(s.first_alarm_index()), std::exp(s.baseline_log()));
  for (std::size_t i = 0; i < run.time_ns.size(); ++i)
    std::printf("series %zu %lld %.9g\n", i, static_cast<long long>(run.time_ns[i]),
                run.features(static_cast<Eigen::Index>(i), 0));
}

int run_ims(const Options& o) {
  const auto series = alarms::series_from_feature_table(o.ims, o.feature_name);
  const int ch = o.channel - 1;
  if (ch < 0 || ch >= static_cast<int>(series.channel_names.size())) usage("--channel outside the table");
  auto options = alarms::shipped_options("ims2");
  options.params = o.alarm;
  std::vector<alarms::Observation> observations;
  options.on_observation = [&](const alarms::Observation& obs) { observations.push_back(obs); };
  const auto result = alarms::run_condition_pipeline(series, options);
  auto scorer_with = [&](std::array<std::int64_t, kLevels> truth) {
    auto engine = std::make_unique<alarms::AlarmEngine>("ims2", series.channel_names, result.factor_names, options.params);
    PrognosisScorer s(std::move(engine), o.params, ch, truth);
    for (const auto& obs : observations) s.observe(obs);
    return s;
  };
  const PrognosisScorer first = scorer_with({0, 0, 0});
  if (first.first_alarm_index() < 0) {
    std::cout << "no degradation alarm on " << series.channel_names[static_cast<std::size_t>(ch)] << ": nothing to score\n";
    return causal::config::kExitFailed;
  }
  if (o.stop_index >= series.time_ns.size()) usage("--stop-index beyond the table");
  const double base = std::exp(first.baseline_log());
  std::vector<double> level(series.time_ns.size());
  for (std::size_t i = 0; i < level.size(); ++i) level[i] = series.values(static_cast<Eigen::Index>(i), ch);
  std::array<std::int64_t, kLevels> truth_index{};
  const auto truth = median_crossings(series.time_ns, level, base, first.first_alarm_index(),
                                      {options.params.warning_ratio, options.params.critical_ratio, o.params.end_of_life_ratio},
                                      static_cast<std::int64_t>(o.stop_index), &truth_index);
  const PrognosisScorer s = scorer_with(truth);
  std::printf("IMS %s, channel %d (%s): first degradation alarm at snapshot %lld, baseline %.5g; truth: 2x at "
              "snapshot %lld, 4x at %lld, end of life (%.3gx, else the stop %llu) at %lld (trailing 5-snapshot median)\n",
              o.ims.c_str(), o.channel, series.channel_names[static_cast<std::size_t>(ch)].c_str(),
              static_cast<long long>(s.first_alarm_index()), base, static_cast<long long>(truth_index[0]),
              static_cast<long long>(truth_index[1]), o.params.end_of_life_ratio,
              static_cast<unsigned long long>(o.stop_index), static_cast<long long>(truth_index[2]));
  std::cout << score_table("IMS: time to 2x, 4x baseline and to the end of life; 90 % intervals", s.scores());
  if (o.trace) print_trace(s);
  return 0;
}

int run_sim(const Options& o) {
  std::array<MethodScores, kMethods> per_kind[2], both;
  int no_alarm = 0;
  for (int kind = 0; kind < 2; ++kind) {
    for (int seed = o.first_seed; seed < o.first_seed + o.seeds; ++seed) {
      SimSpec spec;
      spec.seed = static_cast<std::uint64_t>(seed);
      spec.gaussian = kind == 0;
      spec.episodic = o.episodic;
      const SimRun run = simulate_run_to_failure(spec);
      const PrognosisScorer s = score_simulated_run(run, o.params);
      if (s.first_alarm_index() < 0) ++no_alarm;
      for (int m = 0; m < kMethods; ++m) {
        per_kind[kind][static_cast<std::size_t>(m)].merge(s.scores()[static_cast<std::size_t>(m)]);
        both[static_cast<std::size_t>(m)].merge(s.scores()[static_cast<std::size_t>(m)]);
      }
      if (o.trace) {
        print_trace(s);
        print_series(spec, run, s);
      }
    }
  }
  std::printf("simulated run-to-failure%s: seeds %d..%d x {Gaussian, uniform} noise, acceleration_diffusion %g, forecast_diffusion %g, "
              "pessimistic_z %g, calibration lag %g h memory %g, end of life %.3gx; %d runs without a degradation alarm on the wearing channel\n",
              o.episodic ? " (episodic wear)" : "", o.first_seed, o.first_seed + o.seeds - 1, o.params.trend.acceleration_diffusion, o.params.trend.forecast_diffusion,
              o.params.pessimistic_z, o.params.trend.calibration_lag_hours, o.params.trend.calibration_memory,
              o.params.end_of_life_ratio, no_alarm);
  std::cout << score_table("Gaussian noise", per_kind[0]) << "\n"
            << score_table("uniform noise", per_kind[1]) << "\n"
            << score_table("both", both);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    return o.sim ? run_sim(o) : run_ims(o);
  } catch (const std::exception& e) {
    std::cerr << "causal-prognosis-eval: " << e.what() << "\n";
    return causal::config::kExitUsage;
  }
}
