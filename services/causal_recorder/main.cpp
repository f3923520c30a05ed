// causal-recorder: the historian. Records condition vectors, causal factors, alarms and
// recommendations as CSV files. See --help.
#include "recorder_node.hpp"

#include "causal/history/history_store.hpp"

#include <CLI/CLI.hpp>
#include "causal/config/cli_conventions.hpp"
#include "causal/config/service_options.hpp"
#include <spdlog/spdlog.h>

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::recorder::RecorderOptions o;
  CLI::App app{"causal-recorder: records condition vectors, condition-level causal factors (filter and fixed-lag\n"
               "smoother), alarms and recommendations as CSV files, one file per asset group and stream,\n"
               "flushed as it goes (and with --db to a database). causal-report turns the folder into plots."};
  causal::dds::add_common_options(app, o.dds);
  app.add_option("--out", o.out_dir, "output folder (created; existing files with the same header are appended to)")
      ->required();
  app.add_flag("--sample-level", o.sample_level, "also record sample-level factors (voluminous)");
  app.add_option("--idle-exit", o.idle_exit_s, "exit after this many seconds without data, once data arrived (0 = never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  causal::config::add_max_runtime_option(app, o.max_runtime_s);
  app.add_option("--max-pending", o.max_pending,
                 "factor rows per file waiting for missing outcomes before the oldest is written partially")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--db", o.db_url,
                 "also write the history to a database: sqlite:PATH (a file, WAL) or postgresql://... (libpq URI);\n"
                 "tables and queries: docs/historian.md. Given twice, the last counts (RECORDER_ARGS overrides the unit's)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast)
      ->check([](const std::string& url) { return causal::history::url_problem(url); });
  app.add_option("--retention-days", o.retention_days,
                 "delete database rows whose data time is older than this many days (0 = keep everything)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  CAUSAL_CLI_PARSE(app, argc, argv);
  return causal::dds::run_service(signals, "causal-recorder", o.dds,
                                  [&] { return std::make_unique<causal::recorder::RecorderNode>(std::move(o)); });
}
