// The services' shared command line (add_common_options): the one name per thing with the old spellings as
// aliases, --version, and $FASTRTPS_DEFAULT_PROFILES_FILE honoured like in every Fast DDS application.
#include "causal/dds/participant.hpp"
#include "causal/dds/service_runtime.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using causal::dds::add_common_options;
using causal::dds::choose_profile_files;
using causal::dds::CommonOptions;

const std::string kDds = std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/dds";

// Parses args (without the program name) into fresh options.
CommonOptions parse(std::vector<std::string> args) {
  CLI::App app;
  CommonOptions o;
  add_common_options(app, o);
  std::vector<const char*> argv{"service"};
  for (const auto& a : args) argv.push_back(a.c_str());
  app.parse(static_cast<int>(argv.size()), argv.data());
  return o;
}

TEST(ServiceOptions, NewNamesAndOldAliasesSetTheSameOption) {
  const std::string plant = kDds + "/plant.xml";
  EXPECT_EQ(parse({"--transport", plant}).transport_file, plant);
  EXPECT_EQ(parse({"--dds-transport", plant}).transport_file, plant);
  EXPECT_EQ(parse({"--qos", plant}).qos_file, plant);
  EXPECT_EQ(parse({"--dds-qos", plant}).qos_file, plant);
  EXPECT_TRUE(parse({"--transport", plant}).transport_from_flag);
  EXPECT_FALSE(parse({}).transport_from_flag);
  EXPECT_FALSE(parse({}).qos_from_flag);
  // Without flags: the files the configuration search finds (this build-tree test: the source tree's deploy/dds,
  // also with the package installed in /etc/causal-twin).
  if (std::getenv("CAUSAL_TWIN_DDS_DIR") == nullptr) {
    EXPECT_EQ(parse({}).qos_file, kDds + "/qos.xml");
    EXPECT_EQ(parse({}).transport_file, kDds + "/localhost.xml");
  }
}

TEST(ServiceOptions, VersionFlagPrintsTheProjectVersion) {
  CLI::App app;
  CommonOptions o;
  add_common_options(app, o);
  const char* argv[] = {"service", "--version"};
  try {
    app.parse(2, argv);
    FAIL() << "--version did not stop the parse";
  } catch (const CLI::CallForVersion& e) {
    EXPECT_EQ(std::string(e.what()), CAUSAL_TWIN_VERSION);
    EXPECT_EQ(e.get_exit_code(), 0);
  }
}

TEST(ServiceOptions, DefaultProfilesFileReplacesTheTransportOnlyWithoutFlags) {
  CommonOptions o = parse({});
  auto chosen = choose_profile_files(o, "/etc/site.xml");
  EXPECT_EQ(chosen.files, (std::vector<std::string>{o.qos_file, "/etc/site.xml"}));
  EXPECT_TRUE(chosen.from_environment);
  chosen = choose_profile_files(o, nullptr);
  EXPECT_EQ(chosen.files, (std::vector<std::string>{o.qos_file, o.transport_file}));
  EXPECT_FALSE(chosen.from_environment);
  EXPECT_FALSE(choose_profile_files(o, "").from_environment);
  o = parse({"--transport", kDds + "/plant.xml"});
  chosen = choose_profile_files(o, "/etc/site.xml");
  EXPECT_EQ(chosen.files, (std::vector<std::string>{o.qos_file, kDds + "/plant.xml"}));
  o = parse({"--qos", kDds + "/qos.xml"});
  EXPECT_FALSE(choose_profile_files(o, "/etc/site.xml").from_environment);
}

// A generic Fast DDS profiles file (no causal_twin_participant, a default participant profile with its own name)
// in $FASTRTPS_DEFAULT_PROFILES_FILE: the participant is created from it.
TEST(ServiceOptions, ParticipantUsesTheDefaultProfilesFile) {
  const auto dir = std::filesystem::temp_directory_path() / ("profiles_env_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "site.xml").string();
  std::ofstream(file) << R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <transport_descriptors>
      <transport_descriptor>
        <transport_id>site_udp_loopback</transport_id>
        <type>UDPv4</type>
        <interfaceWhiteList><address>127.0.0.1</address></interfaceWhiteList>
      </transport_descriptor>
    </transport_descriptors>
    <participant profile_name="site_participant" is_default_profile="true">
      <rtps>
        <name>site-participant</name>
        <useBuiltinTransports>false</useBuiltinTransports>
        <userTransports><transport_id>site_udp_loopback</transport_id></userTransports>
        <builtin>
          <metatrafficUnicastLocatorList><locator><udpv4><address>127.0.0.1</address></udpv4></locator></metatrafficUnicastLocatorList>
          <initialPeersList><locator><udpv4><address>127.0.0.1</address></udpv4></locator></initialPeersList>
        </builtin>
      </rtps>
    </participant>
  </profiles>
</dds>
)";
  ::setenv("FASTRTPS_DEFAULT_PROFILES_FILE", file.c_str(), 1);
  const CommonOptions o = parse({"--domain", std::to_string(100 + ::getpid() % 100)});
  causal::dds::DdsSettings settings = causal::dds::to_dds_settings(o, "");
  EXPECT_EQ(settings.profile_files, (std::vector<std::string>{o.qos_file, file}));
  EXPECT_FALSE(settings.participant_profile_required);
  settings.participant_name.clear();  // keep the profile's name: it shows which profile was used
  {
    causal::dds::Participant participant(settings);
    EXPECT_EQ(participant.get()->get_qos().name().to_string(), "site-participant");
  }
  // Fast DDS also loads the file by itself (the variable is set while the factory starts): loading it twice is fine.
  ::unsetenv("FASTRTPS_DEFAULT_PROFILES_FILE");
  std::filesystem::remove_all(dir);
}

}  // namespace
