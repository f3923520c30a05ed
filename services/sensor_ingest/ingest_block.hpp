// sensor-ingest's payloads, DDS-free: one message = one block of N samples x G channels of one asset group,
// with the source's time of the first sample, its sample rate and its own block sequence number. Three
// encodings, told apart by the first byte (so every transport accepts all three):
//
//  JSON (first byte '{'), one object per message (per line on stdin):
//    {"asset_group":"pump-1","channels":["b1","b2"],"sample_rate_hz":20000,"t0_ns":1700000000000000000,
//     "sequence":17,"samples":[[0.1,0.2],[0.3,0.4]],"unit":"g","end_of_segment":false}
//    samples: N rows of G numbers (sample-major); null = a missing value (NaN); unit, end_of_segment optional.
//  CSV (first bytes "#block"): one header line of key=value words, then N lines of G comma-separated numbers:
//    #block asset_group=pump-1 channels=b1,b2 sample_rate_hz=20000 t0_ns=1700000000000000000 sequence=17 samples=2
//    0.1,0.2
//    0.3,0.4
//    (optional words unit=g end_of_segment=1; "nan" is a missing value.)
//  Binary (first bytes "CTB1"), little-endian: magic "CTB1", u16 G, u16 flags (bit 0 end_of_segment),
//    u32 N, u64 sequence, i64 t0_ns, f64 sample_rate_hz (36 bytes), then u16 length + bytes of the asset
//    group, of the unit, of each of the G channel names, then N x G f64 samples, sample-major.
//
// Non-finite values are forwarded, not rejected: the estimator's input screen rejects and counts them per
// channel and raises a data_quality alarm, while the other channels and the sample indices stay intact
// (dropping the block would turn one bad value into a gap in every channel). They are counted here too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "causal/io/name_limits.hpp"

namespace causal::ingest {

struct IngestBlock {
  std::string asset_group;
  std::vector<std::string> channels;  // G names, column order
  std::string unit;
  double sample_rate_hz = 0.0;
  std::int64_t t0_ns = 0;       // source time of samples[0], ns since the Unix epoch (UTC)
  std::uint64_t sequence = 0;   // the source's block counter
  bool end_of_segment = false;  // the source closes a contiguous recording with this block
  std::size_t samples_per_channel = 0;
  std::vector<double> samples;  // N x G, sample-major: samples[n * G + g]
  std::size_t non_finite = 0;   // NaN / Inf values among samples (forwarded; see above)
};

// Why a message was rejected; each is a counter label (reason_name) and a log class.
enum class RejectReason {
  Malformed,     // not JSON / CSV / binary, bad syntax, a value that is not a number
  Truncated,     // binary or CSV block shorter than its header says
  Shape,         // a row with the wrong number of values, no channels, no samples, too many channels
  Field,         // a missing or invalid header field (asset group, sample rate <= 0, ...)
  Oversize,      // more bytes or values than the limits allow
  LayoutChange,  // channels differ from this asset group's earlier blocks
  Duplicate,     // the source's sequence number was seen already (e.g. an MQTT QoS 1 redelivery)
  OutOfOrder,    // sequence or time goes backwards or overlaps the previous block
};
inline constexpr int kRejectReasonCount = 8;
const char* reason_name(RejectReason reason);  // "malformed", "truncated", ...

struct BlockLimits {
  std::size_t max_channels = io::kMaxChannels;  // the IDL's bound on channel_names
  std::size_t max_values = 1u << 20;  // N x G per block (8 MiB of doubles)
  std::size_t max_bytes = 16u << 20;  // encoded message size
  std::size_t max_name_bytes = io::kMaxNameBytes;  // asset group, channel names, unit (the one name limit)
};

struct ParseResult {
  std::optional<IngestBlock> block;  // set when accepted
  RejectReason reason = RejectReason::Malformed;
  std::string detail;  // what is wrong, for the log
};

// Any of the three encodings, chosen by the first byte(s).
[[nodiscard]] ParseResult parse_block(const std::string& message, const BlockLimits& limits = {});
[[nodiscard]] ParseResult parse_json_block(const std::string& message, const BlockLimits& limits = {});
[[nodiscard]] ParseResult parse_csv_block(const std::string& message, const BlockLimits& limits = {});
[[nodiscard]] ParseResult parse_binary_block(const std::string& message, const BlockLimits& limits = {});

// Splits a byte stream (stdin) into messages: JSON lines, CSV blocks (header + N lines), binary blocks
// (length from their header). Bytes that start none of these are returned up to the next line end as one
// message, which parse_block then rejects as malformed (the stream resynchronises on the next line).
class BlockStreamSplitter {
 public:
  explicit BlockStreamSplitter(BlockLimits limits = {}) : limits_(limits) {}
  void append(const char* data, std::size_t n) { buffer_.append(data, n); }
  // The next complete message, or nullopt when more bytes are needed. At end of stream (`eof`) the rest
  // is returned as the last message (a truncated block is then rejected by the parser).
  std::optional<std::string> next(bool eof);

 private:
  BlockLimits limits_;
  std::string buffer_;
  std::size_t start_ = 0;   // consumed prefix of buffer_
  std::uint64_t skip_ = 0;  // bytes of an oversize binary block still to drop
};

}  // namespace causal::ingest
