#include "causal/advice/action_catalogue.hpp"

namespace causal::advice {

const std::vector<std::string>& SeverityActions::at(alarms::Severity s) const {
  switch (s) {
    case alarms::Severity::Critical: return critical;
    case alarms::Severity::Warning: return warning;
    case alarms::Severity::Advisory: break;
  }
  return advisory;
}

std::string ActionCatalogue::asset_type(const std::string& asset_group, const std::string& channel_name) const {
  if (const auto it = assets.find(asset_group + "/" + channel_name); it != assets.end()) return it->second;
  if (const auto it = assets.find(asset_group); it != assets.end()) return it->second;
  return default_asset_type;
}

std::string ActionCatalogue::actions(const std::string& asset_group, const std::string& channel_name,
                                     alarms::Severity s) const {
  const auto it = asset_types.find(asset_type(asset_group, channel_name));
  if (it == asset_types.end()) return "";
  std::string out;
  for (const auto& a : it->second.at(s)) out += (out.empty() ? "" : "; ") + a;
  return out;
}

ActionCatalogue ActionCatalogue::rolling_bearing_defaults() {
  ActionCatalogue c;
  SeverityActions& b = c.asset_types["rolling_bearing"];
  b.advisory = {"inspect it (vibration spectrum, temperature, noise) at the next round", "check its lubrication"};
  b.warning = {"lubricate it (or check the lubricant for debris)", "reduce its load or speed where the process allows",
               "plan its replacement at the next stop"};
  b.critical = {"replace it at the earliest safe stop", "reduce its load until then"};
  return c;
}

}  // namespace causal::advice
