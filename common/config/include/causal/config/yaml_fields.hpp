// Strict access to a YAML parameter file: every key is required unless read with optional(), every
// section rejects keys it does not know, and each error names the file and the dotted key path
// ("estimator.yaml: sample_level.noise.q: must be > 0, got -1").
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace causal::config {

// Invalid configuration is invalid input: services exit with code 2 for it (see run_service).
class ConfigError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

class Section {
 public:
  // Loads a file; throws ConfigError if it is missing or not valid YAML.
  static Section load_file(const std::string& path);
  Section(YAML::Node node, std::string file, std::string path);

  Section child(const std::string& key) const;  // required map
  bool has(const std::string& key) const;

  double number(const std::string& key) const;
  double positive(const std::string& key) const;      // > 0
  double non_negative(const std::string& key) const;  // >= 0
  long integer(const std::string& key, long min, long max) const;
  bool boolean(const std::string& key) const;
  std::string text(const std::string& key) const;
  std::string one_of(const std::string& key, std::initializer_list<const char*> allowed) const;

  // Throws if the section has a key not in `known` (catches typos such as "publish_evry").
  void only(std::initializer_list<const char*> known) const;
  void only(const std::vector<std::string>& known) const;  // a list built from a table of keys

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
  const YAML::Node& node() const { return node_; }

 private:
  YAML::Node field(const std::string& key) const;
  std::string where(const std::string& key) const;

  YAML::Node node_;
  std::string file_;
  std::string path_;
};

}  // namespace causal::config
