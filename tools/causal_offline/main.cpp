// causal-offline: estimate the time-varying SVAR factors of a channels CSV and write them, with standard
// deviations, to a CSV.
//
//   causal-offline data.csv --out factors.csv --estimator rts --lag-order 1 --auto-noise
//   causal-offline - < conditions_ims2-shaft1_meanabs.csv        (a recorder CSV on standard input)
//   causal-offline big.csv --format columns -o factors.cols        (binary float64 columns, no text formatting)
//
// Channels are divided by a robust scale learned on the calibration window before estimation, and the factors
// are written in the file's units (causal/estimation/standardised_estimation.hpp), so the result does not depend on
// each channel's units; --q/--r/--p0 are then in standardised units (--no-standardise: in the file's units).
//
// Exit codes: 0 success; 2 bad input or bad arguments (message names the file and line, or the constant /
// dead channel); 1 other failure, including an estimate that is not finite (message names factor, channel
// and row; never NaN output with exit 0).
#include <CLI/CLI.hpp>

#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "causal/config/cli_conventions.hpp"
#include "causal/io/channel_csv.hpp"
#include "causal/io/input_error.hpp"
#include "offline_run.hpp"

int main(int argc, char** argv) {
  using causal::offline::Estimator;
  CLI::App app{"Estimate causal factors of a channels CSV (filter, fixed-lag smoother or RTS smoother)"};
  std::string input, output = "-";
  causal::offline::OfflineOptions opt;
  bool quiet = false;
  const std::map<std::string, Estimator> estimators{
      {"filter", Estimator::Filter}, {"fixed-lag", Estimator::FixedLag}, {"rts", Estimator::Rts}};
  causal::config::add_version_flag(app);
  app.add_option("input,--csv", input,
                 "Channels CSV: header of channel names, one row per sample; leading n/index/snapshot/time/timestamp/"
                 "time_ns/time_utc columns are not channels (so a causal-recorder conditions_<group>_<feature>.csv "
                 "reads as it is); '-' = standard input")
      ->required();
  app.add_option("--out,-o,--output", output, "Output file ('-' = stdout)")->capture_default_str();
  app.add_option("--estimator", opt.estimator, "filter | fixed-lag | rts")
      ->transform(CLI::CheckedTransformer(estimators, CLI::ignore_case))
      ->default_str("rts");
  app.add_option("--lag", opt.lag, "Fixed-lag smoother lag L (samples)")->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--lag-order", opt.lag_order, "SVAR lag order M")->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_flag("--self-lags", opt.self_lags, "Also regress each channel on its own past values");
  auto* q = app.add_option("--q", opt.noise.q, "Process noise variance per factor and sample (standardised units)")
                ->check(CLI::NonNegativeNumber)->capture_default_str();
  auto* r = app.add_option("--r", opt.noise.r, "Measurement noise variance (standardised units: share of the channel's scale^2)")->check(CLI::PositiveNumber)
                ->capture_default_str();
  app.add_option("--p0", opt.noise.p0, "Initial factor variance (also used when tuning)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  auto* autonoise = app.add_flag("--auto-noise", opt.auto_noise,
                                 "Tune q, r per channel by maximum likelihood on the calibration window");
  app.add_option("--calibration-samples", opt.calibration_samples,
                 "Samples at the start of the file used by --auto-noise (0 = all)")
      ->check(CLI::NonNegativeNumber)->needs(autonoise)->capture_default_str();
  autonoise->excludes(q)->excludes(r);
  bool raw_units = false;
  app.add_flag("--no-standardise", raw_units,
               "Estimate in the file's units (q, r, p0 too) instead of on robustly standardised channels");
  app.add_option("--every", opt.every,
                 "Write every K-th sample only (0, K, 2K, ...; the estimates are those of the full run): the "
                 "factor output is K times smaller in memory and on disk")
      ->check(CLI::PositiveNumber)->capture_default_str();
  const std::map<std::string, causal::offline::OutputFormat> formats{
      {"csv", causal::offline::OutputFormat::Csv}, {"columns", causal::offline::OutputFormat::Columns}};
  app.add_option("--format", opt.format,
                 "csv (shortest round-trip text) | columns (binary: header, then little-endian float64 columns, "
                 "layout in common/io/include/causal/io/numeric_table.hpp; exact and about 10x faster to write)")
      ->transform(CLI::CheckedTransformer(formats, CLI::ignore_case))
      ->default_str("csv");
  app.add_option("--threads", opt.threads,
                 "Threads formatting the CSV numbers (the text is the same; formatting is most of a large run)")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_flag("--quiet", quiet, "No progress messages on stderr");
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return causal::config::kExitUsage;
  }

  opt.standardise = !raw_units;
  std::ostringstream sink;
  std::ostream& log = quiet ? sink : std::cerr;
  try {
    const causal::io::ChannelTable table = causal::io::read_channel_csv(input);
    if (output == "-") {
      causal::offline::run_offline(input, table, opt, std::cout, log);
      std::cout.flush();
      if (!std::cout) throw std::runtime_error("cannot write to stdout");
    } else {
      std::ofstream out(output, std::ios::binary);
      if (!out) throw std::runtime_error("cannot open output file '" + output + "'");
      causal::offline::run_offline(input, table, opt, out, log);
      out.close();
      if (!out) throw std::runtime_error("error writing output file '" + output + "'");
    }
  } catch (const causal::io::InputError& e) {
    std::cerr << "causal-offline: " << e.what() << "\n";
    return causal::config::kExitUsage;
  } catch (const causal::offline::BadInput& e) {
    std::cerr << "causal-offline: " << e.what() << "\n";
    return causal::config::kExitUsage;
  } catch (const causal::offline::EstimationFailed& e) {
    std::cerr << "causal-offline: " << e.what() << "\n";
    return causal::config::kExitFailed;
  } catch (const std::invalid_argument& e) {  // e.g. a model spec the data cannot support
    std::cerr << "causal-offline: " << input << ": " << e.what() << "\n";
    return causal::config::kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "causal-offline: " << e.what() << "\n";
    return causal::config::kExitFailed;
  }
  return 0;
}
