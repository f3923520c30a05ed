// File helpers shared by the tests: a file's whole text, and a fresh folder per test that is removed afterwards.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

namespace causal::test {

// The whole file, byte for byte ("" when it cannot be opened: the caller's expectations then say what is missing).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// <tmp>/<prefix>_<name>_<pid>, emptied and created: the work folder of a test that runs services, kept afterwards
// for their logs.
inline std::filesystem::path fresh_work_dir(const std::string& prefix, const std::string& name) {
  const std::filesystem::path p =
      std::filesystem::temp_directory_path() / (prefix + "_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

// <tmp>/<prefix>_<pid>_<test name>: created empty for the running test, removed with everything in it afterwards.
struct TestTempDir {
  std::filesystem::path path;
  explicit TestTempDir(const std::string& prefix) {
    path = std::filesystem::temp_directory_path() /
           (prefix + "_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TestTempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TestTempDir(const TestTempDir&) = delete;
  TestTempDir& operator=(const TestTempDir&) = delete;
  void write(const std::string& name, const std::string& text) const { std::ofstream(path / name) << text; }
};

}  // namespace causal::test
