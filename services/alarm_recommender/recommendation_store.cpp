#include "recommendation_store.hpp"

#include "causal/dds/cdr_bytes.hpp"
#include "causal/io/file_names.hpp"
#include "causal/state_archive.hpp"
#include "causal_twinPubSubTypes.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>

namespace causal::recommender {

namespace {

constexpr const char* kTag = "alarm_recommender_recommendations";
constexpr std::uint32_t kVersion = 1;
constexpr const char* kSuffix = ".recommendations.state";

}  // namespace

RecommendationStore::RecommendationStore(std::string state_dir) : dir_(std::move(state_dir)) {}

std::string RecommendationStore::path(const std::string& asset_group) const {
  return (std::filesystem::path(dir_) / (io::safe_file_component(asset_group) + kSuffix)).string();
}

void RecommendationStore::record(const causal_twin::Recommendation& r) {
  if (dir_.empty()) return;
  kept_[r.asset_group()][r.recommendation_id()] =
      dds::to_cdr_bytes<causal_twin::RecommendationPubSubType>(r);
  save(r.asset_group());
}

void RecommendationStore::save(const std::string& asset_group) {
  StateWriter out;
  out.begin(kTag, kVersion);
  out.put(asset_group);
  const auto& kept = kept_[asset_group];
  out.put(static_cast<std::uint64_t>(kept.size()));
  for (const auto& [id, bytes] : kept) out.put(bytes);
  try {
    causal::save_state_file(path(asset_group), out.bytes());
  } catch (const causal::StateError& e) {
    if (save_failures_++ % 100 == 0) {
      spdlog::error("recommendation checkpoint not written ({} failures so far): {}", save_failures_, e.what());
    }
  }
}

std::vector<causal_twin::Recommendation> RecommendationStore::load_all() {
  std::vector<causal_twin::Recommendation> out;
  if (dir_.empty()) return out;
  const std::string suffix = kSuffix;
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.size() > suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  for (const auto& file : files) {
    try {
      auto bytes = causal::load_state_file(file);
      if (!bytes) continue;
      StateReader in(std::move(*bytes));
      in.expect(kTag, kVersion);
      const auto group = in.get<std::string>();
      if (path(group) != file) throw causal::StateError("its content is for asset group '" + group + "'");
      const auto n = in.get<std::uint64_t>();
      auto& kept = kept_[group];
      for (std::uint64_t i = 0; i < n; ++i) {
        const auto body = in.get<std::string>();
        causal_twin::Recommendation r;
        if (!dds::from_cdr_bytes<causal_twin::RecommendationPubSubType>(body, r) || r.asset_group() != group) {
          throw causal::StateError("recommendation " + std::to_string(i) + " is not readable");
        }
        kept[r.recommendation_id()] = body;
        out.push_back(std::move(r));
      }
      if (!in.at_end()) throw causal::StateError("unexpected data after the recommendations");
    } catch (const causal::StateError& e) {
      throw causal::StateError("recommendation checkpoint '" + file + "' cannot be used: " + e.what() +
                               ". Move it away (its advice is then not published again)");
    }
  }
  return out;
}

}  // namespace causal::recommender
