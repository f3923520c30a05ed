// causal-recorder: rows of asset_status.csv, one per AssetStatus message (causal_twin/asset_status): the operator's
// line per asset group each time it changed (learning n of N, healthy, stopped, alarm). Every IDL field, in order.
#pragma once

#include "causal_twin.h"

#include <string>
#include <vector>

namespace causal::recorder {

inline constexpr const char* kAssetStatusFile = "asset_status.csv";
// The recorder keeps every change: a KEEP_ALL reader (deploy/dds/qos.xml); views use asset_status_reader (last
// value per group). Named here, not in causal/dds/topics.hpp, as only the recorder reads the history.
inline constexpr const char* kAssetStatusHistoryReader = "asset_status_history_reader";
const std::vector<std::string>& asset_status_header();
std::vector<std::string> asset_status_row(const causal_twin::AssetStatus& s);
// A repeat (transient-local replay, a re-match) has every field equal: the whole row is the signature.
std::string asset_status_signature(const causal_twin::AssetStatus& s);

}  // namespace causal::recorder
