// load_action_catalogue: actions.yaml into the ActionCatalogue (YAML through causal_config, so causal_advice
// itself stays Eigen + std).
#include "causal/advice/recommender_params.hpp"

#include "causal/config/yaml_fields.hpp"

namespace causal::advice {

namespace {

std::vector<std::string> action_list(const config::Section& s, const std::string& key) {
  const YAML::Node n = s.node()[key];
  if (!n) s.fail(key, "missing (a list of one or more actions)");
  if (!n.IsSequence() || n.size() == 0) s.fail(key, "must be a non-empty list of actions");
  std::vector<std::string> out;
  for (const auto& item : n) {
    if (!item.IsScalar() || item.as<std::string>().empty()) s.fail(key, "every action must be non-empty text");
    out.push_back(item.as<std::string>());
  }
  return out;
}

}  // namespace

ActionCatalogue load_action_catalogue(const std::string& path) {
  using config::Section;
  const Section root = Section::load_file(path);
  root.only({"default_asset_type", "asset_types", "assets"});
  ActionCatalogue c;
  c.default_asset_type = root.text("default_asset_type");
  const Section types = root.child("asset_types");
  if (types.node().size() == 0) root.fail("asset_types", "must define at least one asset type");
  for (const auto& kv : types.node()) {
    const std::string name = kv.first.as<std::string>();
    const Section t = types.child(name);
    t.only({"advisory", "warning", "critical"});
    SeverityActions& a = c.asset_types[name];
    a.advisory = action_list(t, "advisory");
    a.warning = action_list(t, "warning");
    a.critical = action_list(t, "critical");
  }
  if (c.asset_types.count(c.default_asset_type) == 0) {
    root.fail("default_asset_type", "'" + c.default_asset_type + "' is not one of asset_types");
  }
  const YAML::Node assets = root.node()["assets"];
  if (!assets) root.fail("assets", "missing (a map, {} for none)");
  if (!assets.IsMap()) root.fail("assets", "must be a map of \"<group>\" or \"<group>/<channel name>\" to an asset type");
  const Section as = root.child("assets");
  for (const auto& kv : assets) {
    const std::string key = kv.first.as<std::string>();
    const std::string type = as.text(key);
    if (c.asset_types.count(type) == 0) as.fail(key, "asset type '" + type + "' is not one of asset_types");
    c.assets[key] = type;
  }
  return c;
}

}  // namespace causal::advice
