// The environment a systemd unit gives a service (its EnvironmentFile lines, systemd.exec(5)) is checked before the
// service starts: systemd passes a misspelt name on silently, and the service would run with its default
// (CAUSAL_TWIN_DOMIAN_ID=5: domain 0; RECOMENDER_ARGS: no options at all). Checked only under systemd
// (INVOCATION_ID is set for every unit), where every variable comes from the operator's env files.
#pragma once

#include <string>
#include <vector>

namespace causal::config {

// The CAUSAL_TWIN_* variables the services read, and the *_ARGS variables the shipped units expand.
const std::vector<std::string>& known_unit_variables();

// "" when `environment` (NAME=value entries) has no unknown CAUSAL_TWIN_* name and no *_ARGS name within two edits
// of a known one; otherwise the message naming the first such variable and the known name closest to it.
std::string unit_environment_problem(const std::vector<std::string>& environment);

// unit_environment_problem() of this process's environment when it runs under systemd, else "".
std::string this_unit_environment_problem();

}  // namespace causal::config
