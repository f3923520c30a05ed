// Parsing of the project's factor names (x{k}{j}, xL{k}{j}, xL2{k}{j}; x10_2, xL10_2, xL2_10_2 for G >= 10) into
// (outcome, regressor, lag), so the engine can attribute each factor to the equation it belongs to.
#pragma once

#include <string>

namespace causal::alarms {

struct FactorRef {
  int outcome = -1;    // 0-based outcome channel k (the equation the factor belongs to)
  int regressor = -1;  // 0-based channel j whose value the factor multiplies
  int lag = -1;        // 0 = instantaneous, 1 = lag 1, ...
  bool valid() const { return outcome >= 0 && regressor >= 0 && lag >= 0; }
};

// Returns an invalid FactorRef when `name` does not follow the convention for `channels` channels.
[[nodiscard]] FactorRef parse_factor_name(const std::string& name, int channels);

}  // namespace causal::alarms
