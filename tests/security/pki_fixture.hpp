// PKIs for the security tests, made by the shipped scripts (deploy/security) in a private temporary folder:
// the tests check what a plant engineer gets, not hand-made files.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "test_files.hpp"

namespace causal::test::security {

namespace fs = std::filesystem;

inline std::string script(const std::string& name) { return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/security/" + name; }

// Runs a shell command quietly; throws with the command when it fails.
inline void run(const std::string& command) {
  if (std::system((command + " > /dev/null 2>&1").c_str()) != 0) throw std::runtime_error("failed: " + command);
}

inline fs::path fresh_dir(const std::string& name) { return causal::test::fresh_work_dir("causal_security", name); }

// deploy/security/make-pki.sh DIR
inline fs::path make_pki(const fs::path& dir) {
  run(script("make-pki.sh") + " '" + dir.string() + "'");
  return dir;
}

// A folder NAME in `pki` assembled from other identities' files (cert, key, permissions), to test mismatches.
inline void assemble_identity(const fs::path& pki, const std::string& name, const fs::path& cert_from,
                              const fs::path& key_from, const fs::path& permissions_from) {
  fs::create_directories(pki / name);
  fs::copy_file(cert_from / "cert.pem", pki / name / "cert.pem", fs::copy_options::overwrite_existing);
  fs::copy_file(key_from / "key.pem", pki / name / "key.pem", fs::copy_options::overwrite_existing);
  fs::copy_file(permissions_from / "permissions.p7s", pki / name / "permissions.p7s",
                fs::copy_options::overwrite_existing);
}

}  // namespace causal::test::security
