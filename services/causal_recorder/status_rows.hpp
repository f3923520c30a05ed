// causal-recorder: rows of asset_status.csv, one per AssetStatus message (causal_twin/asset_status): the operator's
// line per asset group each time it changed (learning n of N, healthy, stopped, alarm). Every IDL field, in order.
#pragma once

#include "causal_twin.h"

#include <string>
#include <vector>

namespace causal::recorder {

inline constexpr const char* kAssetStatusFile = "asset_status.csv";
const std::vector<std::string>& asset_status_header();
std::vector<std::string> asset_status_row(const causal_twin::AssetStatus& s);
// A repeat (transient-local replay, a re-match) has every field equal: the whole row is the signature.
std::string asset_status_signature(const causal_twin::AssetStatus& s);

}  // namespace causal::recorder
