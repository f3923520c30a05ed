// causal-offline core: validate the channel table, choose the noise (given or tuned), run the estimator and
// write the factors CSV. Kept apart from main.cpp (argument parsing) so each stays small.
#pragma once

#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

#include "causal/io/channel_csv.hpp"
#include "causal/estimation/noise_params.hpp"

namespace causal::offline {

enum class Estimator { Filter, FixedLag, Rts };

// Csv: text, shortest round-trip numbers. Columns: binary column file (causal/io/numeric_table.hpp: header,
// then little-endian float64 columns), for outputs too large to format as text quickly.
enum class OutputFormat { Csv, Columns };

struct OfflineOptions {
  Estimator estimator = Estimator::Rts;
  int lag = 50;                  // fixed-lag smoother lag L
  int lag_order = 1;             // M
  bool self_lags = false;
  bool standardise = true;       // estimate on channels divided by their robust scale (scale-invariant)
  estimation::NoiseParams noise;             // used unless auto_noise; standardised units unless standardise = false
  bool auto_noise = false;       // tune q, r per outcome (p0 from noise.p0)
  long calibration_samples = 0;  // first rows used for the scales and tuning; 0 = all
  long every = 1;                // write samples 0, every, 2 every, ... (the full run's estimates)
  OutputFormat format = OutputFormat::Csv;
  int threads = 1;               // CSV formatting threads (the text does not depend on it)
};

// Input the tool refuses (non-finite value, too few channels or samples): exit code 2 like an InputError.
class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The estimate itself failed (a non-finite factor): exit code 1, the message names factor, channel and row.
class EstimationFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Runs the estimator on `table` (read from `path`, used in messages) and writes the factors to `out`:
//   n,<factor names...>,sd_<factor names...>       (n = 0-based sample index)
// as CSV, or as a binary column file with the same columns (options.format).
// Progress, the scales and the tuned noise go to `log`. Throws BadInput for unusable data (naming file and
// line, or the constant channel) and EstimationFailed for a non-finite result (naming factor, channel, row).
void run_offline(const std::string& path, const causal::io::ChannelTable& table, const OfflineOptions& options,
                 std::ostream& out, std::ostream& log);

// 1-based line of data row `row` (0-based) in the CSV file: the header is the first non-blank line and
// every later non-blank line is one row (the rule of read_channel_csv). 0 if the file cannot be read.
std::size_t data_row_line(const std::string& path, long row);

}  // namespace causal::offline
