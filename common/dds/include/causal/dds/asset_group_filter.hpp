// Shards that divide the work: which asset groups an estimator shard owns, and the DDS content filter that
// makes each shard RECEIVE only those (frames and condition inputs), instead of receiving and decoding every
// frame and dropping the others'.
//
// Why a content filter, and why our own filter class:
//  * Partitions would tie every source to the shard layout (a writer publishes into its partitions; one
//    writer for many asset groups would need one writer per shard). A ContentFilteredTopic keeps the sources
//    unaware: the shard's reader announces its filter in discovery and the writer evaluates it.
//  * Fast DDS 2.9 filters on the WRITER side (the filtered-out sample never leaves the source; the reader is
//    sent a GAP, so reliability does not count it as lost) when: the writer has infinite liveliness (ours do),
//    delivery is neither intra-process nor data-sharing (VibrationFrame is unbounded, so data-sharing is never
//    chosen; the SHM and UDP transports are fine), the reader does not use multicast (localhost.xml and
//    plant.xml use unicast), the writer filters for at most writer_resource_limits.reader_filters_allocation
//    readers (32 by default: 32 shards per source), and the WRITER's participant knows the filter class.
//    Otherwise the reader filters on arrival: still correct, only the bandwidth is not saved.
//  * The built-in DDS-SQL filter (=, LIKE, MATCH, AND/OR/NOT, BETWEEN; no IN) would need one "asset_group =
//    'x' OR ..." term per group and cannot express a hash slice; worse, it deserializes the WHOLE sample into
//    a DynamicData per reader per sample (a 32 KiB frame of 4096 doubles), on the source's thread. This
//    filter reads only the asset_group, the first member of VibrationFrame and ConditionVector (a CDR string
//    right after the encapsulation header), and every Participant registers it (participant.cpp), so our
//    sources filter writer-side. A writer without it (a third-party sensor) leaves the filtering to the reader.
//  * A sample whose asset group cannot be read (an encoding this parser does not know) is let through: the
//    estimator checks the owner again and drops it, counted (never lost silently).
//
// Expression syntax (the filter_expression of the ContentFilteredTopic):
//    hash I/N              the asset groups whose FNV-1a hash modulo N is I (--shard-index/--shard-count)
//    groups P1 P2 ...      ids or glob patterns (* any run, ? one character), any of them
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eprosima::fastdds::dds {
class DomainParticipant;
}

namespace causal::dds {

// The filter class name every Participant registers (see register_asset_group_filter).
inline constexpr const char* kAssetGroupFilterClass = "CAUSAL_TWIN_ASSET_GROUP";

// FNV-1a: a stable hash, so every estimator (and every writer evaluating the filter) agrees on a group's shard.
std::uint64_t asset_group_hash(std::string_view asset_group);

// Glob match: '*' any run of characters (also empty), '?' exactly one; everything else literally.
bool glob_match(std::string_view pattern, std::string_view text);

// Which asset groups one shard owns: a hash slice, or a list of ids / glob patterns (any of them), or all.
struct AssetGroupSelection {
  std::vector<std::string> patterns;  // non-empty: the selection is these (ids or globs)
  int hash_index = 0, hash_count = 1; // patterns empty: hash(group) % hash_count == hash_index

  bool all() const { return patterns.empty() && hash_count <= 1; }
  bool matches(std::string_view asset_group) const;
  // The filter expression ("hash 1/4", "groups sim-00* ims2-shaft1"); "" when all().
  std::string expression() const;
  std::string describe() const;  // for logs: "asset groups with hash % 4 == 1", "asset groups sim-00*, ..."
  // Throws std::invalid_argument naming the problem (unknown keyword, index out of range, bad pattern).
  [[nodiscard]] static AssetGroupSelection parse(std::string_view expression);
  static AssetGroupSelection hash_slice(int index, int count);
};

// The asset_group of a serialized VibrationFrame or ConditionVector: the first member, a CDR string after the
// 4-byte encapsulation header (plain CDR, either endianness). nullopt when the payload is another encoding or
// malformed (too short, no terminating NUL, length past the end).
std::optional<std::string_view> leading_cdr_string(const unsigned char* data, std::size_t length);

// Registers the filter class on a participant (once; its writers then filter for readers that use it).
// Returns false when Fast DDS refused the registration.
bool register_asset_group_filter(eprosima::fastdds::dds::DomainParticipant* participant);

}  // namespace causal::dds
