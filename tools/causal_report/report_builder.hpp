// causal-report's work: read a recorder folder, write gnuplot scripts, run gnuplot, write the Markdown
// summary. Exit codes: 0 done, 1 a figure failed to render, 2 missing input (folder, CSVs, asset,
// gnuplot) -- the message names the missing thing.
#pragma once

#include "run_data.hpp"

#include <filesystem>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace causal::report {

struct ReportOptions {
  std::string run_dir;
  std::string out_dir;
  std::string asset;               // empty = every asset in the folder
  std::string gnuplot = "gnuplot";  // program name (PATH) or path
  bool verdict_only = false;        // print the verdict table (verdict.hpp) to stdout, no figures
};

int build_report(const ReportOptions& options, std::ostream& out, std::ostream& err);

// report_<asset>.md: the figures (title, file name) and the first alarm of each channel.
std::string report_markdown(const std::string& asset, const std::string& run_dir,
                            const std::vector<std::pair<std::string, std::string>>& figures,
                            const std::vector<AlarmSpan>& alarms, const std::vector<std::string>& notes);

}  // namespace causal::report
