// sensor-ingest payloads: every encoding decoded against hand-written messages, every malformed case
// rejected with its reason, and the stream splitter cutting a mixed byte stream into the same messages.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "ingest_block.hpp"

using causal::ingest::BlockLimits;
using causal::ingest::BlockStreamSplitter;
using causal::ingest::parse_block;
using causal::ingest::RejectReason;

namespace {

const std::string kJson =
    R"({"asset_group":"pump-1","channels":["b1","b2"],"sample_rate_hz":20000,"t0_ns":1700000000000000000,)"
    R"("sequence":17,"samples":[[0.5,-1.25],[2,3.5],[4,5]],"unit":"g"})";

const std::string kCsv =
    "#block asset_group=pump-1 channels=b1,b2 sample_rate_hz=20000 t0_ns=1700000000000000000 sequence=17 samples=3 "
    "unit=g\n"
    "0.5,-1.25\n2,3.5\n4,5\n";

// Little-endian writers, written out byte by byte (independent of the parser's reader).
void put(std::string& s, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_f64(std::string& s, double d) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &d, 8);
  put(s, bits, 8);
}
void put_str(std::string& s, const std::string& t) {
  put(s, t.size(), 2);
  s += t;
}
std::string binary(std::uint16_t g, std::uint32_t n, const std::vector<double>& values, std::uint16_t flags = 0,
                   double rate = 20000.0) {
  std::string s = "CTB1";
  put(s, g, 2);
  put(s, flags, 2);
  put(s, n, 4);
  put(s, 17, 8);
  put(s, 1700000000000000000ULL, 8);
  put_f64(s, rate);
  put_str(s, "pump-1");
  put_str(s, "g");
  for (std::uint16_t c = 0; c < g; ++c) put_str(s, "b" + std::to_string(c + 1));
  for (const double v : values) put_f64(s, v);
  return s;
}

void expect_reference_block(const causal::ingest::ParseResult& r) {
  ASSERT_TRUE(r.block) << r.detail;
  const auto& b = *r.block;
  EXPECT_EQ(b.asset_group, "pump-1");
  EXPECT_EQ(b.channels, (std::vector<std::string>{"b1", "b2"}));
  EXPECT_EQ(b.unit, "g");
  EXPECT_EQ(b.sample_rate_hz, 20000.0);
  EXPECT_EQ(b.t0_ns, 1700000000000000000LL);
  EXPECT_EQ(b.sequence, 17u);
  EXPECT_FALSE(b.end_of_segment);
  EXPECT_EQ(b.samples_per_channel, 3u);
  EXPECT_EQ(b.samples, (std::vector<double>{0.5, -1.25, 2, 3.5, 4, 5}));
  EXPECT_EQ(b.non_finite, 0u);
}

RejectReason reason_of(const std::string& m, const BlockLimits& limits = {}) {
  const auto r = parse_block(m, limits);
  EXPECT_FALSE(r.block) << "accepted: " << m.substr(0, 80);
  return r.reason;
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST(IngestBlock, JsonCsvAndBinaryDecodeTheSameBlock) {
  expect_reference_block(parse_block(kJson));
  expect_reference_block(parse_block(kCsv));
  expect_reference_block(parse_block(binary(2, 3, {0.5, -1.25, 2, 3.5, 4, 5})));
}

TEST(IngestBlock, EndOfSegmentInEveryEncoding) {
  EXPECT_TRUE(
      parse_block(replaced(kJson, R"("unit":"g")", R"("unit":"g","end_of_segment":true)")).block->end_of_segment);
  EXPECT_TRUE(parse_block(replaced(kCsv, "unit=g", "unit=g end_of_segment=1")).block->end_of_segment);
  EXPECT_TRUE(parse_block(binary(2, 3, {0, 0, 0, 0, 0, 0}, 1)).block->end_of_segment);
}

TEST(IngestBlock, NonFiniteValuesAreForwardedAndCounted) {
  const auto j = parse_block(replaced(kJson, "[2,3.5]", "[null,3.5]"));
  ASSERT_TRUE(j.block);
  EXPECT_TRUE(std::isnan(j.block->samples[2]));
  EXPECT_EQ(j.block->non_finite, 1u);
  const auto c = parse_block(replaced(kCsv, "2,3.5", "nan,inf"));
  ASSERT_TRUE(c.block);
  EXPECT_EQ(c.block->non_finite, 2u);
  const auto b = parse_block(binary(2, 3, {0.5, -1.25, NAN, 3.5, 4, -INFINITY}));
  ASSERT_TRUE(b.block);
  EXPECT_EQ(b.block->non_finite, 2u);
  EXPECT_EQ(b.block->samples[5], -INFINITY);
}

TEST(IngestBlock, MalformedJsonIsRejected) {
  EXPECT_EQ(reason_of(kJson.substr(0, kJson.size() - 1)), RejectReason::Malformed);  // cut short
  EXPECT_EQ(reason_of("[1,2,3]"), RejectReason::Malformed);
  EXPECT_EQ(reason_of("{}"), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kJson, "[2,3.5]", R"([2,"x"])")), RejectReason::Malformed);
  EXPECT_EQ(reason_of("hello world"), RejectReason::Malformed);
  EXPECT_EQ(reason_of(""), RejectReason::Malformed);
}

TEST(IngestBlock, DuplicateJsonKeysAreRejected) {
  // The last value would win in most parsers, the first in some: such a message means what its reader picks.
  const auto top = parse_block(replaced(kJson, R"("unit":"g")", R"("unit":"g","sequence":18)"));
  EXPECT_FALSE(top.block);
  EXPECT_EQ(top.reason, RejectReason::Malformed);
  EXPECT_EQ(top.detail, "duplicate key in a JSON object");
  EXPECT_EQ(reason_of(replaced(kJson, R"("unit":"g")", R"("unit":"g","note":{"a":1,"b":2,"a":3})")),
            RejectReason::Malformed);
  // Extra keys (unique) are ignored as before, whatever they hold.
  const auto extra = parse_block(replaced(kJson, R"("unit":"g")", R"("unit":"g","note":{"a":[1,{"b":null}]})"));
  expect_reference_block(extra);
}

TEST(IngestBlock, JsonNestingIsBoundedAt32Levels) {
  // The top object is level 1: an extra member nested to level 32 is accepted, one to level 33 refused.
  const auto nested = [](int levels) {
    return replaced(kJson, R"("unit":"g")",
                    R"("unit":"g","pad":)" + std::string(static_cast<std::size_t>(levels - 1), '[') +
                        std::string(static_cast<std::size_t>(levels - 1), ']'));
  };
  expect_reference_block(parse_block(nested(32)));
  const auto deep = parse_block(nested(33));
  EXPECT_FALSE(deep.block);
  EXPECT_EQ(deep.reason, RejectReason::Malformed);
  EXPECT_EQ(deep.detail, "JSON nested deeper than 32 levels");
}

// Peak resident memory of this process (the kernel's high-water mark), in MiB.
double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

TEST(IngestBlock, JsonMemoryIsBoundedByTheMessage) {
  // Messages of 16 MiB (the default --max-message-bytes), each shaped to cost the most in a document tree:
  // nested arrays (one allocation per level), a flat array of zeros, one row per value, many members. Each
  // is decoded and refused for its own reason; the process's peak stays under 100 MiB (the message itself
  // plus a copy is 32 MiB; a document tree of the first took more than 1 GiB).
  const std::size_t bytes = (16u << 20) - 64;
  const std::string open = R"({"asset_group":"g","pad":)";
  std::string nested = open + std::string(bytes, '[');
  EXPECT_EQ(parse_block(nested).detail, "JSON nested deeper than 32 levels");
  nested.clear();
  nested.shrink_to_fit();
  std::string zeros = open + "[0";
  while (zeros.size() < bytes) zeros += ",0";
  zeros += "]}";
  EXPECT_EQ(parse_block(zeros).detail, "channels missing or not an array");
  zeros.clear();
  zeros.shrink_to_fit();
  std::string rows = R"({"asset_group":"g","channels":["a"],"samples":[[0])";
  while (rows.size() < bytes) rows += ",[0]";
  rows += "]}";
  const auto many_rows = parse_block(rows);
  EXPECT_EQ(many_rows.reason, RejectReason::Oversize);
  EXPECT_EQ(many_rows.detail, "more than 1048576 rows");
  rows.clear();
  rows.shrink_to_fit();
  std::string members = open + "{";
  for (std::size_t k = 0; members.size() < bytes; ++k) members += "\"" + std::to_string(k) + "\":0,";
  members += R"("end":0}})";
  EXPECT_EQ(parse_block(members).detail, "channels missing or not an array");
  EXPECT_LT(peak_rss_mib(), 100.0);
}

TEST(IngestBlock, MissingOrInvalidFieldsAreRejected) {
  EXPECT_EQ(reason_of(replaced(kJson, R"("asset_group":"pump-1")", R"("asset_group":"")")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kJson, R"("sample_rate_hz":20000)", R"("sample_rate_hz":0)")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kJson, R"("sample_rate_hz":20000)", R"("sample_rate_hz":-5)")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kJson, R"("t0_ns":1700000000000000000)", R"("t0_ns":1.5)")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kJson, R"("sequence":17)", R"("sequence":-1)")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kCsv, " sequence=17", "")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kCsv, "sample_rate_hz=20000", "sample_rate_hz=fast")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kCsv, "unit=g", "colour=red")), RejectReason::Field);
  EXPECT_EQ(reason_of(binary(2, 3, {0, 0, 0, 0, 0, 0}, 0, std::nan(""))), RejectReason::Field);
}

TEST(IngestBlock, CsvMemoryIsBoundedByTheMessage) {
  // 16 MiB of commas as the channel list, then as one row: each field a string would be 16 M strings (about
  // 512 MiB); both are refused by their count before anything is split.
  const std::size_t bytes = (16u << 20) - 256;
  std::string message;
  message.reserve(bytes + 256);  // built in place: the test's own copies would count in its peak too
  message.append("#block asset_group=g channels=").append(bytes, ',').append(
      " sample_rate_hz=1 t0_ns=0 sequence=0 samples=1\n0\n");
  const auto channels = parse_block(message);
  EXPECT_EQ(channels.reason, RejectReason::Shape);
  EXPECT_EQ(channels.detail, std::to_string(bytes + 1) + " channels, at most 64");
  message.clear();
  message.append(kCsv, 0, kCsv.find('\n') + 1).append(bytes, ',').append("\n2,3.5\n4,5\n");
  const auto row = parse_block(message);
  EXPECT_EQ(row.reason, RejectReason::Shape);
  EXPECT_EQ(row.detail, "row 0 has " + std::to_string(bytes + 1) + " values, expected 2");
  EXPECT_LT(peak_rss_mib(), 100.0);
}

TEST(IngestBlock, NamesMeetTheOneNameLimit) {
  // 255 bytes (causal/io/name_limits.hpp) pass, as every reader downstream takes them; 256 are refused here.
  const std::string longest(255, 'g');
  const auto ok = parse_block(replaced(replaced(kJson, R"("pump-1")", "\"" + longest + "\""), R"("b2")",
                                       "\"" + longest + "\""));
  ASSERT_TRUE(ok.block) << ok.detail;
  EXPECT_EQ(ok.block->asset_group, longest);
  EXPECT_EQ(reason_of(replaced(kJson, R"("pump-1")", "\"" + longest + "g\"")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kJson, R"("b2")", "\"" + longest + "g\"")), RejectReason::Field);
  EXPECT_EQ(reason_of(replaced(kCsv, "channels=b1,b2", "channels=b1," + longest + "g")), RejectReason::Field);
}

TEST(IngestBlock, WrongChannelCountIsRejected) {
  EXPECT_EQ(reason_of(replaced(kJson, "[2,3.5]", "[2,3.5,7]")), RejectReason::Shape);
  EXPECT_EQ(reason_of(replaced(kJson, "[2,3.5]", "[2]")), RejectReason::Shape);
  EXPECT_EQ(reason_of(replaced(kJson, R"(["b1","b2"])", "[]")), RejectReason::Shape);
  EXPECT_EQ(reason_of(replaced(kJson, R"([[0.5,-1.25],[2,3.5],[4,5]])", "[]")), RejectReason::Shape);
  EXPECT_EQ(reason_of(replaced(kCsv, "2,3.5", "2,3.5,7")), RejectReason::Shape);
  EXPECT_EQ(reason_of(kCsv + "6,7\n"), RejectReason::Shape);  // more rows than samples=
  EXPECT_EQ(reason_of(binary(0, 3, {})), RejectReason::Shape);
  EXPECT_EQ(reason_of(binary(65, 1, std::vector<double>(65, 0.0))), RejectReason::Shape);
  EXPECT_EQ(reason_of(binary(2, 3, {0, 0, 0, 0, 0, 0, 0})), RejectReason::Shape);  // one double too many
}

TEST(IngestBlock, OversizeIsRejected) {
  BlockLimits small;
  small.max_values = 5;  // the reference block has 6
  EXPECT_EQ(reason_of(kJson, small), RejectReason::Oversize);
  EXPECT_EQ(reason_of(kCsv, small), RejectReason::Oversize);
  EXPECT_EQ(reason_of(binary(2, 3, {0, 0, 0, 0, 0, 0}), small), RejectReason::Oversize);
  BlockLimits tiny_bytes;
  tiny_bytes.max_bytes = 64;
  EXPECT_EQ(reason_of(kJson, tiny_bytes), RejectReason::Oversize);
}

TEST(IngestBlock, TruncatedBlocksAreRejected) {
  const std::string full = binary(2, 3, {0.5, -1.25, 2, 3.5, 4, 5});
  EXPECT_EQ(reason_of(full.substr(0, full.size() - 1)), RejectReason::Truncated);   // inside the samples
  EXPECT_EQ(reason_of(full.substr(0, 40)), RejectReason::Truncated);                // inside the names
  EXPECT_EQ(reason_of(full.substr(0, 20)), RejectReason::Truncated);                // inside the fixed header
  EXPECT_EQ(reason_of(kCsv.substr(0, kCsv.find("4,5"))), RejectReason::Truncated);  // a row missing
}

TEST(IngestBlock, SplitterCutsAMixedStreamIntoMessages) {
  const std::string bin = binary(2, 3, {0.5, -1.25, 2, 3.5, 4, 5});
  const std::string stream = kJson + "\n\n" + kCsv + bin + "garbage line\n" + kJson + "\n" + bin.substr(0, 50);
  // Fed in 7-byte pieces: messages must not depend on how the bytes arrive.
  BlockStreamSplitter splitter;
  std::vector<std::string> messages;
  for (std::size_t at = 0; at < stream.size(); at += 7) {
    splitter.append(stream.data() + at, std::min<std::size_t>(7, stream.size() - at));
    while (auto m = splitter.next(false)) messages.push_back(*m);
  }
  while (auto m = splitter.next(true)) messages.push_back(*m);
  ASSERT_EQ(messages.size(), 6u);
  expect_reference_block(parse_block(messages[0]));
  expect_reference_block(parse_block(messages[1]));
  expect_reference_block(parse_block(messages[2]));
  EXPECT_EQ(parse_block(messages[3]).reason, RejectReason::Malformed);
  expect_reference_block(parse_block(messages[4]));
  EXPECT_EQ(parse_block(messages[5]).reason, RejectReason::Truncated);  // the stream ended inside a block
}

TEST(IngestBlock, SplitterSkipsAnOversizeBinaryBlockWhole) {
  BlockLimits small;
  small.max_values = 5;
  const std::string big = binary(2, 3, {1, 2, 3, 4, 5, 6});
  BlockStreamSplitter splitter(small);
  const std::string stream = big + kJson + "\n";
  splitter.append(stream.data(), stream.size());
  std::vector<std::string> messages;
  while (auto m = splitter.next(true)) messages.push_back(*m);
  ASSERT_EQ(messages.size(), 2u);  // the oversize header (its samples dropped unread), then the JSON block
  EXPECT_EQ(parse_block(messages[0], small).reason, RejectReason::Oversize);
  EXPECT_TRUE(parse_block(messages[1]).block);
}
