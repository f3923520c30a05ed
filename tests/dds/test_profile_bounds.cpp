// Fast DDS XML profile files (deploy/dds/*.xml, or what --profile/$FASTRTPS_DEFAULT_PROFILES_FILE names) are
// configuration, but a bad one must be refused with a message naming the file, never crash or grow the process:
// malformed XML, a file past 1 MiB (refused before Fast DDS reads it whole), nesting thousands deep (tinyxml2 9
// stops at 100 levels), and a DTD "billion laughs" (tinyxml2 expands no declared entities).
#include "causal/dds/participant.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

// One directory per test process (ctest runs the cases in parallel), removed when its cases end.
fs::path dir() {
  struct Cleanup : ::testing::Environment {
    explicit Cleanup(fs::path d) : path(std::move(d)) {}
    void TearDown() override {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
    fs::path path;
  };
  static const fs::path d = [] {
    const fs::path p = fs::temp_directory_path() / ("profile_bounds_" + std::to_string(::getpid()));
    fs::create_directories(p);
    ::testing::AddGlobalTestEnvironment(new Cleanup(p));
    return p;
  }();
  return d;
}

std::string write_profile(const std::string& name, const std::string& text) {
  const fs::path p = dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

// Creates a participant from `file` alone; returns the error message (fails the test if none), checks that the
// answer came within a second and, with `names_file`, that the message names the file.
std::string refusal(const std::string& file, bool names_file = true) {
  causal::dds::DdsSettings s;
  s.profile_files = {file};
  s.domain_id = 0;
  s.security_dir = "off";
  const auto start = std::chrono::steady_clock::now();
  std::string message;
  try {
    causal::dds::Participant p(s);
    ADD_FAILURE() << file << " was loaded";
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1)) << message;
  if (names_file) EXPECT_NE(message.find(file), std::string::npos) << "the message must name the file: " << message;
  return message;
}

long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

const char* kHead = R"(<?xml version="1.0" encoding="UTF-8" ?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <participant profile_name="causal_twin_participant">
      <rtps><name>bounds</name></rtps>
    </participant>
)";

TEST(ProfileBounds, MalformedXmlIsRefusedNamingTheFile) {
  const std::string message = refusal(write_profile("malformed.xml", std::string(kHead) + "  <profiles>\n"));
  EXPECT_NE(message.find("missing or invalid XML"), std::string::npos) << message;
}

TEST(ProfileBounds, AHugeFileIsRefusedBeforeItIsRead) {
  // 64 MiB of comment inside an otherwise valid file: refused by its size, not read.
  const std::string file = (dir() / "huge.xml").string();
  {
    std::ofstream out(file, std::ios::binary);
    out << kHead << "<!-- ";
    const std::string chunk(1u << 20, 'x');  // written in pieces: the test itself stays small
    for (int i = 0; i < 64; ++i) out << chunk;
    out << " -->\n  </profiles>\n</dds>\n";
  }
  const std::string message = refusal(file);
  EXPECT_NE(message.find("larger than 1024 KiB"), std::string::npos) << message;
  EXPECT_LT(peak_rss_kb(), 100 * 1024) << "peak RSS " << peak_rss_kb() << " kB";
  fs::remove(file);
}

TEST(ProfileBounds, DeepNestingIsRefused) {
  std::string deep = kHead;
  for (int i = 0; i < 20000; ++i) deep += "<a>";
  for (int i = 0; i < 20000; ++i) deep += "</a>";
  deep += "\n  </profiles>\n</dds>\n";
  ASSERT_LT(deep.size(), 1u << 20);
  const std::string message = refusal(write_profile("deep.xml", deep));
  EXPECT_NE(message.find("missing or invalid XML"), std::string::npos) << message;
}

TEST(ProfileBounds, DeclaredEntitiesAreNotExpanded) {
  // No participant profile in it: whether Fast DDS takes the file or not, no participant is created, and the
  // entities (10^9 "lol" if expanded) cost nothing.
  std::string laughs = "<?xml version=\"1.0\"?>\n<!DOCTYPE dds [\n  <!ENTITY lol0 \"lol\">\n";
  for (int i = 1; i <= 9; ++i) {
    laughs += "  <!ENTITY lol" + std::to_string(i) + " \"";
    for (int k = 0; k < 10; ++k) laughs += "&lol" + std::to_string(i - 1) + ";";
    laughs += "\">\n";
  }
  laughs += "]>\n<dds xmlns=\"http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles\">\n  <profiles>\n"
            "    <data_writer profile_name=\"laughs\"><topic><name>&lol9;</name></topic></data_writer>\n"
            "  </profiles>\n</dds>\n";
  const std::string message = refusal(write_profile("laughs.xml", laughs), false);
  std::printf("laughs.xml: %s\n", message.c_str());
  EXPECT_LT(peak_rss_kb(), 100 * 1024) << "peak RSS " << peak_rss_kb() << " kB";
}

}  // namespace
