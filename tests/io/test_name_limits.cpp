// The one name limit (causal/io/name_limits.hpp) and the files named after names: every name the limit allows
// (up to 255 bytes, any bytes) gets a state file that can be written and read back, with a suffix and the
// ".tmp" of the atomic replace inside the file system's 255 bytes; distinct names get distinct files.
#include "causal/estimation/state_archive.hpp"
#include "causal/io/file_names.hpp"
#include "causal/io/group_state_files.hpp"
#include "causal/io/name_limits.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <unistd.h>

using causal::io::kMaxFileComponentBytes;
using causal::io::kMaxNameBytes;
using causal::io::name_problem;
using causal::io::safe_file_component;

TEST(NameLimits, NamesOfOneTo255BytesAreAllowed) {
  EXPECT_STREQ(name_problem(""), "empty");
  EXPECT_EQ(name_problem("a"), nullptr);
  EXPECT_EQ(name_problem(std::string(kMaxNameBytes, 'x')), nullptr);
  EXPECT_STREQ(name_problem(std::string(kMaxNameBytes + 1, 'x')), "longer than 255 bytes");
}

TEST(NameLimits, FileComponentsStayShortAndDistinct) {
  // Short names keep their file names (existing state files are found again).
  EXPECT_EQ(safe_file_component("pump-1"), "pump-1");
  std::set<std::string> seen;
  for (std::size_t n = 1; n <= kMaxNameBytes; ++n) {
    for (const char c : {'a', '/'}) {
      const std::string component = safe_file_component(std::string(n, c));
      EXPECT_LE(component.size(), kMaxFileComponentBytes) << n << " x " << c;
      EXPECT_TRUE(seen.insert(component).second) << "two names share " << component;
    }
  }
  // Names equal in their first 200 bytes still get distinct files.
  const std::string stem(200, 'g');
  EXPECT_NE(safe_file_component(stem + std::string(55, 'a')), safe_file_component(stem + std::string(55, 'b')));
}

// The one file-name sanitiser, for state files and the recorder's CSV files alike: safe names unchanged, any
// other byte replaced and a hash of the original appended, so "a b" and "a_b" never share a file.
TEST(NameLimits, FileComponentsReplaceUnsafeBytesAndKeepIdsApart) {
  EXPECT_EQ(safe_file_component("a.b_c-D9"), "a.b_c-D9");
  const std::string slash = safe_file_component("ims2/shaft 1");
  EXPECT_EQ(slash.substr(0, 13), "ims2_shaft_1-");
  EXPECT_EQ(slash.size(), 12u + 1u + 8u);
  EXPECT_NE(safe_file_component("ims2_shaft_1"), slash);
  EXPECT_EQ(safe_file_component("..").substr(0, 3), "_.-");  // no "..", no hidden file
  EXPECT_EQ(safe_file_component(".hidden").substr(0, 8), "_hidden-");
  EXPECT_EQ(safe_file_component("../etc/passwd").find('/'), std::string::npos);
  EXPECT_EQ(safe_file_component("").substr(0, 1), "-");
  EXPECT_EQ(safe_file_component("\xC3\xA9t\xC3\xA9").substr(0, 6), "__t__-");  // UTF-8 replaced byte-wise
}

TEST(NameLimits, AStateFileForTheLongestNames) {
  const auto dir = std::filesystem::temp_directory_path() / ("causal_name_limits_" + std::to_string(getpid()));
  {
    causal::io::GroupStateFiles files(dir.string(), ".estimator.state");
    for (const std::string& name : {std::string(kMaxNameBytes, 'z'), std::string(kMaxNameBytes, '\xc3'),
                                    std::string(242, 'y') + "/../x"}) {
      ASSERT_TRUE(files.save(name, [&](causal::estimation::StateWriter& w) { w.put(name); })) << files.last_error();
      const auto payload = files.load(name);
      ASSERT_TRUE(payload);
      causal::estimation::StateReader r(*payload);
      EXPECT_EQ(r.get<std::string>(), name);
      EXPECT_EQ(std::filesystem::path(files.path(name)).parent_path(), dir);
    }
    EXPECT_EQ(files.saves(), 3u);
    EXPECT_EQ(files.failures(), 0u);
  }
  std::filesystem::remove_all(dir);
}
