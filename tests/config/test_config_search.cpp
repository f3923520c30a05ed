// The configuration search order: flag, environment folder, the source tree (only for a build-tree binary),
// /etc/causal-twin, installed defaults. Truth: the files this test places in its own temporary folders.
#include "causal/config/config_search.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_files.hpp"

namespace fs = std::filesystem;
using causal::config::ConfigChoice;
using causal::config::ConfigKind;
using causal::config::find_config_file;
using causal::config::SearchRoots;

namespace {

class Places : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* d : {"env", "etc", "installed", "tree"}) fs::create_directories(root_ / d);
    roots_.env_dir = dir("env");
    roots_.env_name = "CAUSAL_TWIN_DDS_DIR";
    roots_.etc_dir = dir("etc");
    roots_.installed_dir = dir("installed");
    roots_.build_tree_dir = dir("tree");
  }
  std::string dir(const std::string& name) const { return (root_ / name).string(); }
  void put(const std::string& where, const std::string& file) const { std::ofstream(root_ / where / file) << "x"; }

  const causal::test::TestTempDir temp_{"config_search"};
  const fs::path& root_ = temp_.path;
  SearchRoots roots_;
};

// An installed binary (no build tree): environment, /etc, installed defaults.
TEST_F(Places, FirstPlaceHoldingTheFileWinsInTheDocumentedOrder) {
  roots_.build_tree_dir.clear();
  put("installed", "qos.xml");
  ConfigChoice c = find_config_file("qos.xml", "", roots_);
  EXPECT_EQ(c.path, dir("installed") + "/qos.xml");
  EXPECT_EQ(c.origin, "the installed defaults");
  put("etc", "qos.xml");
  c = find_config_file("qos.xml", "", roots_);
  EXPECT_EQ(c.path, dir("etc") + "/qos.xml");
  put("env", "qos.xml");
  c = find_config_file("qos.xml", "", roots_);
  EXPECT_EQ(c.path, dir("env") + "/qos.xml");
  EXPECT_EQ(c.origin, "$CAUSAL_TWIN_DDS_DIR");
  EXPECT_EQ(c.describe("qos.xml"), dir("env") + "/qos.xml (from $CAUSAL_TWIN_DDS_DIR)");
  // The flag beats every place, and is taken as given (CLI11 checks that it exists).
  c = find_config_file("qos.xml", "/somewhere/mine.xml", roots_);
  EXPECT_EQ(c.path, "/somewhere/mine.xml");
  EXPECT_EQ(c.origin, "flag");
}

// A build-tree binary on a machine where the package is installed: its own source tree beats /etc and the
// installed defaults (tests never run against the installed configuration); the environment still wins.
TEST_F(Places, BuildTreeBinaryPrefersItsSourceTreeToAnInstalledPackage) {
  put("installed", "qos.xml");
  put("etc", "qos.xml");
  ConfigChoice c = find_config_file("qos.xml", "", roots_);
  EXPECT_EQ(c.path, dir("etc") + "/qos.xml");  // not in the tree: /etc is next
  put("tree", "qos.xml");
  c = find_config_file("qos.xml", "", roots_);
  EXPECT_EQ(c.path, dir("tree") + "/qos.xml");
  EXPECT_EQ(c.origin, "the source tree (build-tree binary)");
  put("env", "qos.xml");
  EXPECT_EQ(find_config_file("qos.xml", "", roots_).path, dir("env") + "/qos.xml");
}

TEST_F(Places, EachFileIsSearchedOnItsOwn) {
  put("etc", "qos.xml");
  put("installed", "localhost.xml");
  EXPECT_EQ(find_config_file("qos.xml", "", roots_).path, dir("etc") + "/qos.xml");
  EXPECT_EQ(find_config_file("localhost.xml", "", roots_).path, dir("installed") + "/localhost.xml");
}

TEST_F(Places, NotFoundNamesEveryPlaceLookedAt) {
  const ConfigChoice c = find_config_file("alarms.yaml", "", roots_);
  EXPECT_FALSE(c.found());
  ASSERT_EQ(c.searched.size(), 4u);
  EXPECT_EQ(c.describe("alarms.yaml"), "alarms.yaml not found (looked in: " + dir("env") + ", " + dir("tree") + ", " +
                                           dir("etc") + ", " + dir("installed") + ")");
}

TEST_F(Places, WithoutTheBuildTreeTheSourceTreeIsNeverRead) {
  put("tree", "qos.xml");
  roots_.build_tree_dir.clear();  // what process_roots does for an installed binary
  EXPECT_FALSE(find_config_file("qos.xml", "", roots_).found());
}

TEST(IsInsideDir, ComparesWholeComponents) {
  EXPECT_TRUE(causal::config::is_inside_dir("/work/build/services/x", "/work/build"));
  EXPECT_TRUE(causal::config::is_inside_dir("/work/build/services/x", "/work/build/"));
  EXPECT_TRUE(causal::config::is_inside_dir("/work/build/a/../services/x", "/work/build"));
  EXPECT_FALSE(causal::config::is_inside_dir("/work/build2/services/x", "/work/build"));
  EXPECT_FALSE(causal::config::is_inside_dir("/usr/bin/causal-estimator", "/work/build"));
  EXPECT_FALSE(causal::config::is_inside_dir("/work", "/work/build"));
}

// This test binary lives in the build tree, so the process roots include the source tree's deploy folder,
// searched right after the environment folder.
TEST(ProcessRoots, BuildTreeBinaryFallsBackToDeployAndHonoursTheEnvironment) {
  ::unsetenv("CAUSAL_TWIN_DDS_DIR");
  const SearchRoots roots = causal::config::process_roots(ConfigKind::Dds);
  EXPECT_EQ(roots.build_tree_dir, std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds");
  EXPECT_EQ(roots.etc_dir, "/etc/causal-twin");
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  EXPECT_EQ(roots.installed_dir, (exe.parent_path().parent_path() / "share/causal-twin/dds").string());
  // Also with a package installed (/etc/causal-twin/qos.xml present): the source tree comes first.
  EXPECT_EQ(find_config_file("qos.xml", "", ConfigKind::Dds).path, std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds/qos.xml");
  const std::string mine = (fs::temp_directory_path() / "config_search_env").string();
  fs::create_directories(mine);
  std::ofstream(mine + "/alarms.yaml") << "x";
  ::setenv("CAUSAL_TWIN_CONFIG_DIR", mine.c_str(), 1);
  EXPECT_EQ(find_config_file("alarms.yaml", "", ConfigKind::Parameters).path, mine + "/alarms.yaml");
  EXPECT_EQ(find_config_file("alarms.yaml", "", ConfigKind::Parameters).origin, "$CAUSAL_TWIN_CONFIG_DIR");
  ::unsetenv("CAUSAL_TWIN_CONFIG_DIR");
  EXPECT_EQ(find_config_file("alarms.yaml", "", ConfigKind::Parameters).path,
            std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/config/alarms.yaml");
  fs::remove_all(mine);
}

}  // namespace
