#include "causal/config/yaml_fields.hpp"

#include "causal/config/yaml_bounds.hpp"

#include <cmath>
#include <set>

namespace causal::config {

namespace {

// The value of `key` as T; what YAML cannot read as T fails naming the key, what it must be and what it is.
template <class T>
T converted(const Section& section, const YAML::Node& n, const std::string& key, const char* must_be) {
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    section.fail(key, std::string("must be ") + must_be + ", got '" + n.as<std::string>("?") + "'");
  }
}

}  // namespace

Section Section::load_file(const std::string& path) {
  const std::string text = read_yaml_file(path);
  check_yaml_bounds(text, path);  // before yaml-cpp builds a tree of it (yaml_bounds.hpp)
  try {
    YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) throw ConfigError(path + ": the top level must be a map of sections");
    return Section(root, path, "");
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path + ": invalid YAML: " + e.what());
  }
}

Section::Section(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

std::string Section::where(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

void Section::fail(const std::string& key, const std::string& problem) const {
  throw ConfigError(file_ + ": " + where(key) + ": " + problem);
}

bool Section::has(const std::string& key) const { return node_[key].IsDefined() && !node_[key].IsNull(); }

YAML::Node Section::field(const std::string& key) const {
  const YAML::Node n = node_[key];
  if (!n.IsDefined() || n.IsNull()) fail(key, "missing (required)");
  return n;
}

Section Section::child(const std::string& key) const {
  const YAML::Node n = field(key);
  if (!n.IsMap()) fail(key, "must be a section (a map of keys)");
  return Section(n, file_, where(key));
}

double Section::number(const std::string& key) const {
  const double v = converted<double>(*this, field(key), key, "a number");
  if (!std::isfinite(v)) fail(key, "must be finite");
  return v;
}

double Section::positive(const std::string& key) const {
  const double v = number(key);
  if (!(v > 0.0)) fail(key, "must be > 0, got " + std::to_string(v));
  return v;
}

double Section::non_negative(const std::string& key) const {
  const double v = number(key);
  if (v < 0.0) fail(key, "must be >= 0, got " + std::to_string(v));
  return v;
}

long Section::integer(const std::string& key, long min, long max) const {
  const long v = converted<long>(*this, field(key), key, "a whole number");
  if (v < min || v > max) {
    fail(key, "must be in " + std::to_string(min) + ".." + std::to_string(max) + ", got " + std::to_string(v));
  }
  return v;
}

bool Section::boolean(const std::string& key) const {
  return converted<bool>(*this, field(key), key, "true or false");
}

std::string Section::text(const std::string& key) const {
  const YAML::Node n = field(key);
  if (!n.IsScalar()) fail(key, "must be a single value");
  return n.as<std::string>();
}

std::string Section::one_of(const std::string& key, std::initializer_list<const char*> allowed) const {
  const std::string v = text(key);
  std::string list;
  for (const char* a : allowed) {
    if (v == a) return v;
    list += list.empty() ? a : std::string(", ") + a;
  }
  fail(key, "must be one of " + list + ", got '" + v + "'");
}

void Section::only(std::initializer_list<const char*> known) const {
  only(std::vector<std::string>(known.begin(), known.end()));
}

void Section::only(const std::vector<std::string>& known) const {
  const std::set<std::string> allowed(known.begin(), known.end());
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (allowed.count(key) == 0) {
      std::string list;
      for (const auto& a : allowed) list += list.empty() ? a : ", " + a;
      fail(key, "unknown key (known here: " + list + ")");
    }
  }
}

}  // namespace causal::config
