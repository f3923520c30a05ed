// The action catalogue (deploy/config/actions.yaml): what to do on an asset whose degradation alarm has no
// reliable upstream lever, by asset type and alarm severity. One plain struct; its loader
// (recommender_params.hpp: load_action_catalogue) rejects unknown keys, unknown asset types and empty action lists
// with the file and key in the message.
#pragma once

#include "causal/alarms/alarm_event.hpp"

#include <map>
#include <string>
#include <vector>

namespace causal::advice {

struct SeverityActions {
  std::vector<std::string> advisory, warning, critical;  // most urgent first; never empty once loaded
  const std::vector<std::string>& at(alarms::Severity s) const;
};

struct ActionCatalogue {
  std::string default_asset_type = "rolling_bearing";
  std::map<std::string, SeverityActions> asset_types;
  // Asset type by "<asset group>" (every channel) or "<asset group>/<channel name>" (wins over the group).
  std::map<std::string, std::string> assets;

  std::string asset_type(const std::string& asset_group, const std::string& channel_name) const;
  // The catalogue's actions for that asset at that severity, joined: "a; b; c". Empty when the type is
  // unknown (only a hand-built catalogue can have that: the loader refuses it).
  std::string actions(const std::string& asset_group, const std::string& channel_name, alarms::Severity s) const;

  // Built-in defaults for rolling bearings (the shipped file's content), for tests and tools.
  static ActionCatalogue rolling_bearing_defaults();
};

}  // namespace causal::advice
