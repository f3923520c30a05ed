#include "causal/config/yaml_bounds.hpp"

#include "causal/config/yaml_fields.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>

namespace causal::config {
namespace {

// Counts nodes and nesting event by event (no tree is built) and refuses anchors and aliases at the first one.
class BoundsCheck : public YAML::EventHandler {
 public:
  explicit BoundsCheck(std::string source) : source_(std::move(source)) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { node(mark, anchor); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    fail(mark, "aliases (*name) are not allowed in a parameter file");
  }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, const std::string&) override {
    node(mark, anchor);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    open(mark, anchor);
  }
  void OnSequenceEnd() override { --depth_; }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    open(mark, anchor);
  }
  void OnMapEnd() override { --depth_; }

 private:
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& problem) const {
    throw ConfigError(source_ + ": line " + std::to_string(mark.line + 1) + ": " + problem);
  }
  void node(const YAML::Mark& mark, YAML::anchor_t anchor) {
    if (anchor != YAML::NullAnchor) fail(mark, "anchors (&name) are not allowed in a parameter file");
    if (++nodes_ > kMaxYamlNodes) fail(mark, "more than " + std::to_string(kMaxYamlNodes) + " values");
  }
  void open(const YAML::Mark& mark, YAML::anchor_t anchor) {
    node(mark, anchor);
    if (++depth_ > kMaxYamlDepth) fail(mark, "nested deeper than " + std::to_string(kMaxYamlDepth) + " levels");
  }

  std::string source_;
  std::size_t nodes_ = 0, depth_ = 0;
};

}  // namespace

std::string read_yaml_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open the parameter file");
  std::string text(kMaxYamlBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw ConfigError(path + ": cannot read the parameter file");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxYamlBytes) {
    throw ConfigError(path + ": larger than " + std::to_string(kMaxYamlBytes / 1024) + " KiB (not a parameter file)");
  }
  return text;
}

void check_yaml_bounds(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  BoundsCheck check(source);
  try {
    parser.HandleNextDocument(check);
  } catch (const YAML::ParserException&) {
    // Syntax errors are reported by the loader, with its own wording.
  }
}

}  // namespace causal::config
