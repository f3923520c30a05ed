// The action catalogue loader (services/alarm_recommender/action_catalogue.cpp): the shipped file loads and
// matches the built-in defaults; mistakes are ConfigErrors naming the file and the key.
#include "causal/advice/recommender_params.hpp"

#include "config_test_util.hpp"

#include <gtest/gtest.h>

#include <string>

namespace causal::advice {
namespace {

using causal::alarms::Severity;
using causal::test::config_error;
using causal::test::mutated_copy;

const std::string kShipped = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/actions.yaml";

TEST(ActionCatalogue, ShippedFileLoadsWithTheRollingBearingDefaults) {
  const ActionCatalogue c = load_action_catalogue(kShipped);
  const ActionCatalogue d = ActionCatalogue::rolling_bearing_defaults();
  EXPECT_EQ(c.default_asset_type, "rolling_bearing");
  ASSERT_EQ(c.asset_types.count("rolling_bearing"), 1u);
  for (Severity s : {Severity::Advisory, Severity::Warning, Severity::Critical}) {
    EXPECT_EQ(c.asset_types.at("rolling_bearing").at(s), d.asset_types.at("rolling_bearing").at(s));
    EXPECT_FALSE(c.actions("ims2", "bearing1", s).empty());
  }
  EXPECT_NE(c.actions("g", "b", Severity::Warning).find("lubricate"), std::string::npos);
  EXPECT_NE(c.actions("g", "b", Severity::Critical).find("replace"), std::string::npos);
}

TEST(ActionCatalogue, AssetTypePerChannelWinsOverTheGroup) {
  const std::string p = mutated_copy(kShipped, "assets.yaml", [](YAML::Node& d) {
    d["asset_types"]["gearbox"]["advisory"].push_back("check the oil");
    d["asset_types"]["gearbox"]["warning"].push_back("sample the oil for debris");
    d["asset_types"]["gearbox"]["critical"].push_back("stop the gearbox");
    d["assets"]["plant"] = "gearbox";
    d["assets"]["plant/bearing1"] = "rolling_bearing";
  });
  const ActionCatalogue c = load_action_catalogue(p);
  EXPECT_EQ(c.asset_type("plant", "gear"), "gearbox");
  EXPECT_EQ(c.asset_type("plant", "bearing1"), "rolling_bearing");
  EXPECT_EQ(c.asset_type("other", "x"), "rolling_bearing");
  EXPECT_EQ(c.actions("plant", "gear", Severity::Critical), "stop the gearbox");
}

TEST(ActionCatalogue, MistakesNameTheFileAndKey) {
  auto error_of = [](const char* name, const std::function<void(YAML::Node&)>& f) {
    const std::string p = mutated_copy(kShipped, name, f);
    return config_error([&] { load_action_catalogue(p); });
  };
  EXPECT_HAS(error_of("typo.yaml", [](YAML::Node& d) { d["asset_type"] = "x"; }), "asset_type");
  EXPECT_HAS(error_of("sev.yaml", [](YAML::Node& d) { d["asset_types"]["rolling_bearing"]["severe"].push_back("x"); }),
             "asset_types.rolling_bearing");
  EXPECT_HAS(error_of("empty.yaml", [](YAML::Node& d) { d["asset_types"]["rolling_bearing"]["warning"] = YAML::Node(YAML::NodeType::Sequence); }),
             "asset_types.rolling_bearing.warning: must be a non-empty list");
  EXPECT_HAS(error_of("missing.yaml", [](YAML::Node& d) { d["asset_types"]["rolling_bearing"].remove("critical"); }),
             "asset_types.rolling_bearing.critical");
  EXPECT_HAS(error_of("default.yaml", [](YAML::Node& d) { d["default_asset_type"] = "pump"; }),
             "default_asset_type: 'pump' is not one of asset_types");
  EXPECT_HAS(error_of("unknown.yaml", [](YAML::Node& d) { d["assets"]["ims2"] = "pump"; }),
             "assets.ims2: asset type 'pump' is not one of asset_types");
}

}  // namespace

}  // namespace causal::advice
