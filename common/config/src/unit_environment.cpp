#include "causal/config/unit_environment.hpp"

#include <algorithm>
#include <cstdlib>
#include <numeric>

extern char** environ;

namespace causal::config {

namespace {

// Levenshtein distance: the number of single-character edits between two names.
std::size_t edits(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

const std::vector<std::string>& known_unit_variables() {
  static const std::vector<std::string> names{
      "CAUSAL_TWIN_DOMAIN_ID", "CAUSAL_TWIN_SECURITY_DIR", "CAUSAL_TWIN_CONFIG_DIR", "CAUSAL_TWIN_DDS_DIR",
      "ESTIMATOR_ARGS",        "INGEST_ARGS",              "RECOMMENDER_ARGS",       "RECORDER_ARGS",
      "SENSOR_ARGS",           "WEB_ARGS"};
  return names;
}

std::string unit_environment_problem(const std::vector<std::string>& environment) {
  const auto& known = known_unit_variables();
  for (const auto& entry : environment) {
    const std::string name = entry.substr(0, entry.find('='));
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::string closest;
    std::size_t distance = std::string::npos;
    for (const auto& k : known) {
      const std::size_t d = edits(name, k);
      if (d < distance) {
        distance = d;
        closest = k;
      }
    }
    const bool ours = name.rfind("CAUSAL_TWIN_", 0) == 0;
    if (!ours && !(ends_with(name, "_ARGS") && distance <= 2)) continue;
    return "unknown variable " + name + " in the unit's environment (its env files in /etc/causal-twin)" +
           (distance <= 3 ? "; did you mean " + closest + "?" : "") + " Known: " +
           std::accumulate(std::next(known.begin()), known.end(), known.front(),
                           [](std::string a, const std::string& b) { return a + ", " + b; });
  }
  return "";
}

std::string this_unit_environment_problem() {
  const char* invocation = std::getenv("INVOCATION_ID");
  if (invocation == nullptr || *invocation == '\0') return "";
  std::vector<std::string> environment;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) environment.emplace_back(*e);
  return unit_environment_problem(environment);
}

}  // namespace causal::config
