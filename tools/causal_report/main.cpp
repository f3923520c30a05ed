// causal-report: renders a causal-recorder folder as PNG figures (gnuplot) and a Markdown summary.
#include "report_builder.hpp"

#include "causal/config/cli_conventions.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  causal::report::ReportOptions o;
  CLI::App app{"causal-report: turns a causal-recorder folder into figures a person reads at a glance:\n"
               "condition trends with alarm times, causal-factor trajectories with +-2 sd bands (filter and\n"
               "fixed-lag smoother) and an alarm timeline with root causes, plus report_<asset>.md.\n"
               "Exit codes: 0 done, 1 a figure failed, 2 missing input (folder, CSVs, asset, gnuplot)."};
  app.add_option("--run", o.run_dir, "folder written by causal-recorder --out")->required();
  auto* out = app.add_option("--out", o.out_dir, "folder for the PNGs, report_<asset>.md and the gnuplot scripts "
                                                 "(created; required unless --verdict-only)");
  app.add_flag("--verdict-only", o.verdict_only,
               "print the verdict per asset group (status, first alarm, root cause, top recommendation) and exit");
  app.add_option("--asset-group,--asset", o.asset, "only this asset group (default: every asset in the folder)");
  causal::config::add_version_flag(app);
  app.add_option("--gnuplot", o.gnuplot, "gnuplot program (name on PATH or path)")->capture_default_str();
  CAUSAL_CLI_PARSE(app, argc, argv);
  if (!o.verdict_only && out->count() == 0) {
    std::cerr << "causal-report: --out is required (or --verdict-only)\n";
    return causal::config::kExitUsage;
  }
  return causal::report::build_report(o, std::cout, std::cerr);
}
