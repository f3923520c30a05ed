// Shared helpers of the parameter-loader tests: mutate a shipped YAML file, write the copy, expect errors.
#pragma once

#include "causal/config/yaml_fields.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace causal::test {

// A directory of this test process only: ctest runs every test case as its own process, in parallel, and
// cases that wrote the same file name in a shared directory read each other's half-written files. The
// directory is removed when the process's tests end.
inline std::filesystem::path process_temp_dir() {
  struct Cleanup : ::testing::Environment {
    explicit Cleanup(std::filesystem::path d) : dir(std::move(d)) {}
    void TearDown() override {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
    std::filesystem::path dir;
  };
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::path(::testing::TempDir()) / ("causal_config_tests_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    ::testing::AddGlobalTestEnvironment(new Cleanup(d));  // gtest owns it
    return d;
  }();
  return dir;
}

inline std::string temp_yaml_path(const std::string& name) { return (process_temp_dir() / name).string(); }

// Writes `text` byte for byte to a fresh file `name` in this process's temp dir and returns its path.
inline std::string write_yaml(const std::string& name, const std::string& text) {
  const std::string p = temp_yaml_path(name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// Loads `source`, applies `mutate` to the document, writes it to a temp file and returns its path.
inline std::string mutated_copy(const std::string& source, const std::string& name,
                                const std::function<void(YAML::Node&)>& mutate) {
  YAML::Node doc = YAML::LoadFile(source);
  mutate(doc);
  YAML::Emitter emitter;
  emitter << doc;
  const std::string path = temp_yaml_path(name);
  std::ofstream(path) << emitter.c_str() << "\n";
  return path;
}

// Runs f, expects causal::config::ConfigError and returns its message.
template <typename F>
std::string config_error(F&& f) {
  try {
    f();
  } catch (const causal::config::ConfigError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected ConfigError, got another exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected ConfigError, nothing was thrown";
  return "";
}

}  // namespace causal::test

#define EXPECT_HAS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << "message: '" << (haystack) << "'"
