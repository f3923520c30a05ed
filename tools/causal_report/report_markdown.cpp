#include "report_builder.hpp"

#include <algorithm>
#include <map>
#include <sstream>

namespace causal::report {

namespace {
// Markdown table cells: a '|' would split the cell, a line break would end the row.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += "\\|";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out.empty() ? "-" : out;
}
}  // namespace

std::string report_markdown(const std::string& asset, const std::string& run_dir,
                            const std::vector<std::pair<std::string, std::string>>& figures,
                            const std::vector<AlarmSpan>& alarms, const std::vector<std::string>& notes) {
  std::ostringstream md;
  md << "# Causal twin report: " << asset << "\n\n";
  md << "Recorded run: `" << run_dir << "`\n\n";
  md << "## Figures\n\n";
  for (const auto& [title, file] : figures) md << "- [" << title << "](" << file << ")\n";
  md << "\n";
  for (const auto& [title, file] : figures) md << "### " << title << "\n\n![" << title << "](" << file << ")\n\n";
  if (!notes.empty()) {
    md << "## Notes\n\n";
    for (const auto& n : notes) md << "- " << n << "\n";
    md << "\n";
  }

  md << "## Alarms: first alarm per channel\n\n";
  std::map<int, const AlarmSpan*> first;
  std::map<std::string, int> by_severity;
  for (const auto& a : alarms) {
    ++by_severity[to_string(a.max_severity)];
    if (a.raised_utc.empty()) continue;
    auto& f = first[a.channel];
    if (f == nullptr || a.raised < f->raised) f = &a;
  }
  if (first.empty()) {
    md << "No alarms recorded.\n";
    return md.str();
  }
  md << "| Channel | First raised (UTC) | Severity | Kind | Root cause | Cleared (UTC) |\n"
     << "|---|---|---|---|---|---|\n";
  for (const auto& [channel, a] : first) {
    std::string severity = to_string(a->first_severity);
    if (a->max_severity != a->first_severity) severity += std::string(" (escalated to ") + to_string(a->max_severity) + ")";
    std::string root = a->root_cause_name;
    if (root.empty() && a->root_cause_channel > 0) root = "channel " + std::to_string(a->root_cause_channel);
    md << "| " << cell(a->channel_name.empty() ? "channel " + std::to_string(channel) : a->channel_name) << " | "
       << cell(a->raised_utc) << " | " << severity << " | " << cell(a->kind) << " | " << cell(root) << " | "
       << (a->cleared ? cell(a->cleared_utc) : "still active") << " |\n";
  }
  md << "\n" << alarms.size() << " alarm(s) in total";
  std::string sep = ": ";
  for (const auto& [sev, count] : by_severity) {
    md << sep << count << " " << sev;
    sep = ", ";
  }
  md << " (highest severity reached).\n";
  return md.str();
}

}  // namespace causal::report
