// Helpers for the causal_io tests: a self-deleting temp dir, file writers (plain and gzip), and the
// locations of the fixtures / shipped data slice / optional shared full data set.
#pragma once

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "causal/io/input_error.hpp"

#ifndef CAUSAL_IO_FIXTURE_DIR
#error "CAUSAL_IO_FIXTURE_DIR must point at tests/data"
#endif

namespace causal::io::test {

inline std::string fixture(const std::string& name) { return std::string(CAUSAL_IO_FIXTURE_DIR) + "/" + name; }
inline std::string deploy_data(const std::string& rel) {
  return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/" + rel;
}
// Full IMS test-2 folder in ../shared (optional on a developer machine).
inline std::string shared_ims2() { return std::string(CAUSAL_TWIN_SHARED_DIR) + "/data/ims2"; }
inline bool shared_available() { return std::filesystem::is_directory(shared_ims2() + "/raw"); }

// The InputError read() must throw for `path`; a test failure (and a placeholder error) when it throws none.
template <typename Read>
InputError input_error_of(const std::string& path, Read read) {
  try {
    read();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for " << path;
  return InputError(path, 0, "none");
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

class TempDir {
 public:
  TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "causal_io_test_XXXXXX").string();
    if (mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  const std::string& path() const { return path_; }

  std::string write(const std::string& name, const std::string& content) const {
    const std::string p = file(name);
    std::ofstream f(p, std::ios::binary);
    f << content;
    return p;
  }
  std::string write_gz(const std::string& name, const std::string& content) const {
    const std::string p = file(name);
    gzFile gz = gzopen(p.c_str(), "wb9");
    if (gz == nullptr) throw std::runtime_error("gzopen failed");
    gzwrite(gz, content.data(), static_cast<unsigned>(content.size()));
    gzclose(gz);
    return p;
  }

 private:
  std::string path_;
};

}  // namespace causal::io::test
