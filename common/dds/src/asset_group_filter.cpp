#include "causal/dds/asset_group_filter.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/topic/IContentFilter.hpp>
#include <fastdds/dds/topic/IContentFilterFactory.hpp>

#include <cstring>
#include <sstream>
#include <stdexcept>

namespace causal::dds {

std::uint64_t asset_group_hash(std::string_view asset_group) {
  std::uint64_t h = 14695981039346656037ULL;  // the published offset basis (main had a digit missing)
  for (unsigned char c : asset_group) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

bool glob_match(std::string_view pattern, std::string_view text) {
  // Iterative with one backtrack point (the last '*'): linear in practice, no recursion.
  std::size_t p = 0, t = 0, star = std::string_view::npos, mark = 0;
  while (t < text.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
      ++p;
      ++t;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      mark = t;
    } else if (star != std::string_view::npos) {
      p = star + 1;
      t = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

bool AssetGroupSelection::matches(std::string_view asset_group) const {
  if (!patterns.empty()) {
    for (const auto& p : patterns) {
      if (glob_match(p, asset_group)) return true;
    }
    return false;
  }
  if (hash_count <= 1) return true;
  return asset_group_hash(asset_group) % static_cast<std::uint64_t>(hash_count) == static_cast<std::uint64_t>(hash_index);
}

std::string AssetGroupSelection::expression() const {
  if (!patterns.empty()) {
    std::string e = "groups";
    for (const auto& p : patterns) e += " " + p;
    return e;
  }
  if (hash_count <= 1) return {};
  return "hash " + std::to_string(hash_index) + "/" + std::to_string(hash_count);
}

std::string AssetGroupSelection::describe() const {
  if (!patterns.empty()) {
    std::string d = "asset groups ";
    for (std::size_t i = 0; i < patterns.size(); ++i) d += (i ? ", " : "") + patterns[i];
    return d;
  }
  if (hash_count <= 1) return "every asset group";
  return "asset groups with FNV-1a hash % " + std::to_string(hash_count) + " == " + std::to_string(hash_index);
}

AssetGroupSelection AssetGroupSelection::hash_slice(int index, int count) {
  if (count < 1 || index < 0 || index >= count) {
    throw std::invalid_argument("shard " + std::to_string(index) + " of " + std::to_string(count) +
                                ": the index must be in 0.." + std::to_string(count - 1));
  }
  AssetGroupSelection s;
  s.hash_index = index;
  s.hash_count = count;
  return s;
}

AssetGroupSelection AssetGroupSelection::parse(std::string_view expression) {
  std::istringstream in{std::string(expression)};
  std::string keyword;
  if (!(in >> keyword)) return {};  // empty: every asset group
  if (keyword == "hash") {
    std::string slice, extra;
    in >> slice;
    const auto slash = slice.find('/');
    int index = -1, count = 0;
    try {
      if (slash == std::string::npos) throw std::invalid_argument("no slash");
      std::size_t used = 0;
      index = std::stoi(slice.substr(0, slash), &used);
      if (used != slash) throw std::invalid_argument("index");
      count = std::stoi(slice.substr(slash + 1), &used);
      if (used != slice.size() - slash - 1) throw std::invalid_argument("count");
    } catch (const std::exception&) {
      throw std::invalid_argument("asset-group filter '" + std::string(expression) + "': expected 'hash I/N'");
    }
    if (in >> extra) throw std::invalid_argument("asset-group filter '" + std::string(expression) + "': text after 'hash I/N'");
    return hash_slice(index, count);
  }
  if (keyword == "groups") {
    AssetGroupSelection s;
    std::string p;
    while (in >> p) s.patterns.push_back(p);
    if (s.patterns.empty()) {
      throw std::invalid_argument("asset-group filter '" + std::string(expression) + "': 'groups' needs ids or patterns");
    }
    return s;
  }
  throw std::invalid_argument("asset-group filter '" + std::string(expression) + "': unknown keyword '" + keyword +
                              "' (expected 'hash I/N' or 'groups P...')");
}

std::optional<std::string_view> leading_cdr_string(const unsigned char* data, std::size_t length) {
  // Encapsulation: 2 bytes representation id (0x0000 CDR_BE, 0x0001 CDR_LE), 2 bytes options.
  if (data == nullptr || length < 8 || data[0] != 0) return std::nullopt;
  const bool little = data[1] == 1;
  if (!little && data[1] != 0) return std::nullopt;  // PL_CDR, XCDR2: not parsed here
  const unsigned char* b = data + 4;
  const std::uint32_t n = little ? (std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 |
                                    std::uint32_t(b[3]) << 24)
                                 : (std::uint32_t(b[3]) | std::uint32_t(b[2]) << 8 | std::uint32_t(b[1]) << 16 |
                                    std::uint32_t(b[0]) << 24);
  // n counts the terminating NUL.
  if (n == 0 || n > length - 8) return std::nullopt;
  const char* s = reinterpret_cast<const char*>(b + 4);
  if (s[n - 1] != '\0') return std::nullopt;
  return std::string_view(s, n - 1);
}

namespace {

using eprosima::fastdds::dds::IContentFilter;
using eprosima::fastdds::dds::IContentFilterFactory;
using eprosima::fastrtps::types::ReturnCode_t;

struct AssetGroupFilter final : IContentFilter {
  AssetGroupSelection selection;
  bool evaluate(const SerializedPayload& payload, const FilterSampleInfo&, const GUID_t&) const override {
    const auto group = leading_cdr_string(payload.data, payload.length);
    return !group || selection.matches(*group);  // unreadable: let through, the estimator checks again (counted)
  }
};

struct AssetGroupFilterFactory final : IContentFilterFactory {
  ReturnCode_t create_content_filter(const char*, const char*, const eprosima::fastdds::dds::TopicDataType*,
                                     const char* filter_expression, const ParameterSeq&,
                                     IContentFilter*& filter_instance) override {
    try {
      auto* existing = static_cast<AssetGroupFilter*>(filter_instance);
      if (filter_expression == nullptr) {
        // Only the parameters changed: ours has none, keep the filter as it is.
        return existing != nullptr ? ReturnCode_t::RETCODE_OK : ReturnCode_t::RETCODE_BAD_PARAMETER;
      }
      AssetGroupSelection selection = AssetGroupSelection::parse(filter_expression);
      if (existing != nullptr) {
        existing->selection = std::move(selection);
      } else {
        auto* f = new AssetGroupFilter();
        f->selection = std::move(selection);
        filter_instance = f;
      }
      return ReturnCode_t::RETCODE_OK;
    } catch (const std::exception&) {
      return ReturnCode_t::RETCODE_BAD_PARAMETER;  // the original filter (if any) is kept, as the interface asks
    }
  }
  ReturnCode_t delete_content_filter(const char*, IContentFilter* filter_instance) override {
    delete static_cast<AssetGroupFilter*>(filter_instance);
    return ReturnCode_t::RETCODE_OK;
  }
};

}  // namespace

bool register_asset_group_filter(eprosima::fastdds::dds::DomainParticipant* participant) {
  static AssetGroupFilterFactory factory;  // stateless; outlives every participant
  if (participant->lookup_content_filter_factory(kAssetGroupFilterClass) != nullptr) return true;
  return participant->register_content_filter_factory(kAssetGroupFilterClass, &factory) == ReturnCode_t::RETCODE_OK;
}

}  // namespace causal::dds
