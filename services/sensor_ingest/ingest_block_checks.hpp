// The checks every encoding of ingest_block.hpp shares once its header is decoded (one place, so JSON, CSV and
// binary blocks are refused for the same reasons with the same words).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "ingest_block.hpp"

namespace causal::ingest::detail {

[[nodiscard]] ParseResult reject(RejectReason reason, std::string detail);
// Counts the non-finite samples (forwarded, see ingest_block.hpp) and wraps the block.
[[nodiscard]] ParseResult accept(IngestBlock block);
// Asset group, unit, channel names and sample rate against the limits; nullopt when fine.
[[nodiscard]] std::optional<ParseResult> check_header(const IngestBlock& b, const BlockLimits& limits);
// n samples per channel of g channels: at least one, at most limits.max_values in all.
[[nodiscard]] std::optional<ParseResult> check_count(std::size_t n, std::size_t g, const BlockLimits& limits);

}  // namespace causal::ingest::detail
