// Ready-made condition features (a condition-monitoring system that computes RMS or mean |x| per channel itself):
// one message per snapshot, published by sensor-ingest on causal_twin/condition_input. Two encodings, one line each
// (so every transport and the stdin splitter keep a message whole):
//  JSON:  {"asset_group":"pump-1","feature":"meanabs","channels":["b1","b2"],"time_ns":1700000000000000000,
//          "sequence":17,"values":[0.12,0.31],"discontinuity":false}
//  CSV:   #features asset_group=pump-1 feature=meanabs channels=b1,b2 time_ns=1700000000000000000 sequence=17 values=0.12,0.31
// sequence is the source's snapshot counter (it becomes the snapshot index: keep it across restarts of the source);
// discontinuity is optional. Rejections use the raw blocks' reasons (ingest_block.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ingest_block.hpp"

namespace causal::ingest {

struct FeatureRow {
  std::string asset_group;
  std::string feature;
  std::vector<std::string> channels;
  std::vector<double> values;  // one per channel
  std::int64_t time_ns = 0;
  std::uint64_t sequence = 0;
  bool discontinuity = false;
  std::size_t non_finite = 0;
};

struct FeatureParseResult {
  std::optional<FeatureRow> row;
  RejectReason reason = RejectReason::Malformed;
  std::string detail;
};

// True when the message is a feature row (JSON with "values" and no "samples", or a "#features" line), so that
// parse_block is not asked.
bool is_feature_row(const std::string& message);
[[nodiscard]] FeatureParseResult parse_feature_row(const std::string& message, const BlockLimits& limits = {});

}  // namespace causal::ingest
