#include "causal/dds/group_partitions.hpp"

#include <fnmatch.h>

#include <algorithm>

namespace causal::dds {
namespace {

// Text between the next `open` and its `close` from `pos` on (moves `pos` past it); "" when there is none.
// `found` tells an empty element (<partition></partition>: the empty partition) from none.
std::string next_element(const std::string& text, const std::string& name, std::size_t& pos, bool& found) {
  found = false;
  const std::string open = "<" + name + ">", close = "</" + name + ">", empty = "<" + name + "/>";
  const std::size_t a = text.find(open, pos), e = text.find(empty, pos);
  if (e != std::string::npos && (a == std::string::npos || e < a)) {
    pos = e + empty.size();
    found = true;
    return {};
  }
  if (a == std::string::npos) return {};
  const std::size_t b = text.find(close, a + open.size());
  if (b == std::string::npos) return {};
  pos = b + close.size();
  found = true;
  return text.substr(a + open.size(), b - a - open.size());
}

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

std::vector<std::string> elements(const std::string& text, const std::string& name) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  bool found = false;
  for (std::string v = next_element(text, name, pos, found); found; v = next_element(text, name, pos, found)) {
    out.push_back(trimmed(v));
  }
  return out;
}

// Topics and partitions of every <publish> (or <subscribe>) criteria in one rule; no <partitions> in a
// criteria = the empty partition (Fast DDS's PermissionsParser::parse_criteria).
void read_criteria(const std::string& rule, const std::string& kind, std::vector<std::string>& topics,
                   std::vector<std::string>& partitions) {
  for (const std::string& criteria : elements(rule, kind)) {
    for (const std::string& t : elements(criteria, "topic")) topics.push_back(t);
    const std::vector<std::string> named = elements(criteria, "partition");
    if (named.empty()) {
      partitions.emplace_back();
    } else {
      partitions.insert(partitions.end(), named.begin(), named.end());
    }
  }
}

bool names_topic(const std::vector<std::string>& patterns, const std::string& topic) {
  return std::any_of(patterns.begin(), patterns.end(),
                     [&](const std::string& p) { return fnmatch(p.c_str(), topic.c_str(), FNM_NOESCAPE) == 0; });
}

}  // namespace

bool partitions_allow_group(const std::vector<std::string>& partitions, const std::string& group) {
  if (partitions.empty()) return true;
  const std::string wanted = group_partition(group);
  for (const std::string& p : partitions) {
    if (p.empty() || p == wanted) return true;
  }
  return false;
}

GrantedPartitions GrantedPartitions::parse(const std::string& grant_xml) {
  GrantedPartitions g;
  // Rules in document order: <allow_rule> and <deny_rule> elements, whichever comes next.
  std::size_t pos = 0;
  while (true) {
    const std::size_t allow = grant_xml.find("<allow_rule>", pos), deny = grant_xml.find("<deny_rule>", pos);
    if (allow == std::string::npos && deny == std::string::npos) break;
    const bool is_allow = deny == std::string::npos || (allow != std::string::npos && allow < deny);
    const std::string name = is_allow ? "allow_rule" : "deny_rule";
    bool found = false;
    std::size_t at = is_allow ? allow : deny;
    const std::string body = next_element(grant_xml, name, at, found);
    if (!found) break;
    pos = at;
    Rule r;
    r.allow = is_allow;
    read_criteria(body, "publish", r.publish_topics, r.publish_partitions);
    read_criteria(body, "subscribe", r.subscribe_topics, r.subscribe_partitions);
    g.rules_.push_back(std::move(r));
  }
  return g;
}

std::vector<std::string> GrantedPartitions::for_endpoint(const std::string& topic, bool publish) const {
  for (const Rule& r : rules_) {
    const auto& topics = publish ? r.publish_topics : r.subscribe_topics;
    if (!names_topic(topics, topic)) continue;
    if (!r.allow) return {};
    std::vector<std::string> out = publish ? r.publish_partitions : r.subscribe_partitions;
    const bool empty_granted = std::find(out.begin(), out.end(), std::string()) != out.end();
    out.erase(std::remove(out.begin(), out.end(), std::string()), out.end());
    if (out.empty()) return {};
    if (empty_granted) out.insert(out.begin(), std::string());
    return out;
  }
  return {};
}

std::string partitions_property(const std::vector<std::string>& partitions) {
  std::string out;
  for (std::size_t i = 0; i < partitions.size(); ++i) out += (i == 0 ? "" : ";") + partitions[i];
  return out;
}

}  // namespace causal::dds
