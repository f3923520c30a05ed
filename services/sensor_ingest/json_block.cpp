// JSON blocks (ingest_block.hpp) decoded by events (nlohmann's SAX interface), never into a document tree: a
// tree costs tens of bytes per value and one allocation per array, so a 16 MiB message of nested arrays took
// more than a gigabyte. Here the memory of a message is bounded by what is kept of it: the samples (8 bytes per
// number, at most limits.max_values), one count per row, at most max_channels + 1 channel names, and one 8-byte
// key hash per object member for the duplicate check. Nesting deeper than kMaxJsonDepth stops the parse at the
// first level too deep; a key that appears twice in one object is refused ("duplicate key"), as the meaning of
// such a message depends on the parser (RFC 8259, section 4: names SHOULD be unique).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ingest_block.hpp"
#include "ingest_block_checks.hpp"

namespace causal::ingest {

namespace {

using detail::accept;
using detail::check_count;
using detail::check_header;
using detail::reject;

// A block needs 3 levels (object, samples, row); anything deeper is padding or an attack.
constexpr std::size_t kMaxJsonDepth = 32;
constexpr std::uint32_t kNotArray = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

// Where a value sits: what it means depends only on its container and, in the top object, on its key.
enum class Where { Top, Channels, Samples, Row, Ignored };

// The top object's fields: their state after the parse (NotArray: channels given, but not as an array).
enum class Field { Missing, Set, Bad, NotArray };

struct Frame {
  Where where;
  bool object;
  std::vector<std::uint64_t> key_hashes;  // objects only: one per member, sorted at its end
};

class JsonBlockEvents {
 public:
  using json = nlohmann::json;
  explicit JsonBlockEvents(const BlockLimits& limits) : limits_(limits) {}

  bool null() { return scalar(Kind::Null, 0.0); }
  bool boolean(bool v) {
    if (top_field() && key_ == "end_of_segment") {
      block_.end_of_segment = v;
      eos_ = Field::Set;
      return true;
    }
    return scalar(Kind::Other, 0.0);
  }
  bool number_integer(json::number_integer_t v) {
    if (top_field() && key_ == "t0_ns") return set_t0(v, true);
    if (top_field() && key_ == "sequence") return set_sequence(v >= 0, static_cast<std::uint64_t>(v));
    return scalar(Kind::Number, static_cast<double>(v));
  }
  bool number_unsigned(json::number_unsigned_t v) {
    if (top_field() && key_ == "t0_ns") {
      return set_t0(static_cast<std::int64_t>(v), v <= static_cast<std::uint64_t>(INT64_MAX));
    }
    if (top_field() && key_ == "sequence") return set_sequence(true, v);
    return scalar(Kind::Number, static_cast<double>(v));
  }
  bool number_float(json::number_float_t v, const json::string_t& /*text*/) {
    if (top_field() && (key_ == "t0_ns" || key_ == "sequence")) return scalar(Kind::Other, 0.0);
    return scalar(Kind::Number, v);
  }
  bool string(json::string_t& v) {
    if (top_field() && key_ == "asset_group") {
      block_.asset_group = std::move(v);
      group_ = Field::Set;
      return true;
    }
    if (top_field() && key_ == "unit") {
      block_.unit = std::move(v);
      unit_ = Field::Set;
      return true;
    }
    if (!frames_.empty() && frames_.back().where == Where::Channels) {
      ++channel_count_;
      if (block_.channels.size() <= limits_.max_channels) block_.channels.push_back(std::move(v));
      return true;
    }
    return scalar(Kind::Other, 0.0);
  }
  bool binary(json::binary_t& /*v*/) { return scalar(Kind::Other, 0.0); }

  bool start_object(std::size_t /*n*/) { return open(true); }
  bool start_array(std::size_t /*n*/) { return open(false); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool key(json::string_t& k) {
    frames_.back().key_hashes.push_back(std::hash<std::string>{}(k));
    if (frames_.size() == 1) key_ = std::move(k);
    return true;
  }
  bool parse_error(std::size_t /*position*/, const std::string& /*token*/, const nlohmann::detail::exception&) {
    return false;
  }

  // The block once the parse succeeded, checked in the order of the fields' documentation.
  ParseResult finish();
  // The refusal that stopped the parse early, if any (otherwise the text is not valid JSON).
  const std::optional<ParseResult>& stopped() const { return stopped_; }

 private:
  enum class Kind { Null, Number, Other };

  bool top_field() const { return frames_.size() == 1 && frames_.back().where == Where::Top; }
  bool stop(RejectReason reason, std::string detail) {
    stopped_ = reject(reason, std::move(detail));
    return false;
  }
  bool set_t0(std::int64_t v, bool ok) {
    block_.t0_ns = v;
    t0_ = ok ? Field::Set : Field::Bad;
    return true;
  }
  bool set_sequence(bool ok, std::uint64_t v) {
    block_.sequence = v;
    seq_ = ok ? Field::Set : Field::Bad;
    return true;
  }
  bool add_row(std::uint32_t size) {
    if (rows_.size() >= limits_.max_values) {
      return stop(RejectReason::Oversize, "more than " + std::to_string(limits_.max_values) + " rows");
    }
    rows_.push_back(size);
    return true;
  }
  bool scalar(Kind kind, double value);
  bool open(bool object);
  bool close();
  void mark_bad_top_field();

  BlockLimits limits_;
  std::vector<Frame> frames_;
  std::string key_;  // the top object's current key
  IngestBlock block_;
  Field group_ = Field::Missing, channels_ = Field::Missing, unit_ = Field::Missing, rate_ = Field::Missing;
  Field t0_ = Field::Missing, seq_ = Field::Missing, eos_ = Field::Missing, samples_ = Field::Missing;
  std::size_t channel_count_ = 0;
  std::vector<std::uint32_t> rows_;  // values per row, kNotArray for a row that is not an array
  std::size_t first_non_number_row_ = kNone;
  std::optional<ParseResult> stopped_;
};

void JsonBlockEvents::mark_bad_top_field() {
  if (key_ == "asset_group") group_ = Field::Bad;
  if (key_ == "channels") channels_ = Field::NotArray;
  if (key_ == "unit") unit_ = Field::Bad;
  if (key_ == "sample_rate_hz") rate_ = Field::Bad;
  if (key_ == "t0_ns") t0_ = Field::Bad;
  if (key_ == "sequence") seq_ = Field::Bad;
  if (key_ == "end_of_segment") eos_ = Field::Bad;
  if (key_ == "samples") samples_ = Field::Bad;
}

bool JsonBlockEvents::scalar(Kind kind, double value) {
  if (frames_.empty()) return stop(RejectReason::Malformed, "JSON payload is not an object");
  switch (frames_.back().where) {
    case Where::Top:
      if (key_ == "sample_rate_hz" && kind == Kind::Number) {
        block_.sample_rate_hz = value;
        rate_ = Field::Set;
      } else {
        mark_bad_top_field();
      }
      return true;
    case Where::Channels:
      channels_ = Field::Bad;  // a name that is not a string
      return true;
    case Where::Samples:
      return add_row(kNotArray);
    case Where::Row:
      if (kind == Kind::Other && first_non_number_row_ == kNone) first_non_number_row_ = rows_.size() - 1;
      if (block_.samples.size() >= limits_.max_values) {
        return stop(RejectReason::Oversize, "more than " + std::to_string(limits_.max_values) + " values");
      }
      block_.samples.push_back(kind == Kind::Number ? value : std::numeric_limits<double>::quiet_NaN());
      ++rows_.back();
      return true;
    case Where::Ignored:
      return true;
  }
  return true;
}

bool JsonBlockEvents::open(bool object) {
  if (frames_.size() >= kMaxJsonDepth) {
    return stop(RejectReason::Malformed, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  }
  Where where = Where::Ignored;
  if (frames_.empty()) {
    if (!object) return stop(RejectReason::Malformed, "JSON payload is not an object");
    where = Where::Top;
  } else {
    switch (frames_.back().where) {
      case Where::Top:
        if (!object && key_ == "channels" && channels_ == Field::Missing) {
          channels_ = Field::Set;
          where = Where::Channels;
        } else if (!object && key_ == "samples") {
          samples_ = Field::Set;
          where = Where::Samples;
        } else {
          mark_bad_top_field();
        }
        break;
      case Where::Channels:
        channels_ = Field::Bad;
        break;
      case Where::Samples:
        if (!add_row(object ? kNotArray : 0)) return false;
        if (!object) where = Where::Row;
        break;
      case Where::Row:
        // A container where a number belongs: counted as one value of its row, then refused as not a number.
        if (!scalar(Kind::Other, 0.0)) return false;
        break;
      case Where::Ignored:
        break;
    }
  }
  frames_.push_back(Frame{where, object, {}});
  return true;
}

bool JsonBlockEvents::close() {
  auto& hashes = frames_.back().key_hashes;
  std::sort(hashes.begin(), hashes.end());
  if (std::adjacent_find(hashes.begin(), hashes.end()) != hashes.end()) {
    return stop(RejectReason::Malformed, "duplicate key in a JSON object");
  }
  frames_.pop_back();
  return true;
}

ParseResult JsonBlockEvents::finish() {
  IngestBlock& b = block_;
  if (group_ != Field::Set) return reject(RejectReason::Field, "asset_group missing or not a string");
  if (channels_ == Field::Missing || channels_ == Field::NotArray) return reject(RejectReason::Field, "channels missing or not an array");
  if (channels_ == Field::Bad) return reject(RejectReason::Field, "channel names must be strings");
  if (unit_ == Field::Bad) return reject(RejectReason::Field, "unit is not a string");
  if (rate_ != Field::Set) return reject(RejectReason::Field, "sample_rate_hz missing or not a number");
  if (t0_ != Field::Set) return reject(RejectReason::Field, "t0_ns missing or not an integer");
  if (seq_ != Field::Set) return reject(RejectReason::Field, "sequence missing or not an integer >= 0");
  if (eos_ == Field::Bad) return reject(RejectReason::Field, "end_of_segment is not a boolean");
  if (channel_count_ > limits_.max_channels) {
    return reject(RejectReason::Shape, std::to_string(channel_count_) + " channels, at most " +
                                           std::to_string(limits_.max_channels));
  }
  if (auto bad = check_header(b, limits_)) return *bad;
  if (samples_ != Field::Set) return reject(RejectReason::Field, "samples missing or not an array of rows");
  const std::size_t g = b.channels.size();
  if (auto bad = check_count(rows_.size(), g, limits_)) return *bad;
  for (std::size_t n = 0; n < rows_.size(); ++n) {
    if (rows_[n] != g) {
      return reject(RejectReason::Shape, "row " + std::to_string(n) + " has " +
                                             (rows_[n] == kNotArray ? std::string("no") : std::to_string(rows_[n])) +
                                             " values, expected " + std::to_string(g));
    }
    if (n == first_non_number_row_) {
      return reject(RejectReason::Malformed, "row " + std::to_string(n) + ": a value is not a number");
    }
  }
  b.samples_per_channel = rows_.size();
  return accept(std::move(b));
}

}  // namespace

ParseResult parse_json_block(const std::string& message, const BlockLimits& limits) {
  if (message.size() > limits.max_bytes)
    return reject(RejectReason::Oversize, "message of " + std::to_string(message.size()) + " bytes");
  JsonBlockEvents events(limits);
  const bool parsed = nlohmann::json::sax_parse(message, &events, nlohmann::json::input_format_t::json,
                                                /*strict=*/true);
  if (!parsed) return events.stopped() ? *events.stopped() : reject(RejectReason::Malformed, "not valid JSON");
  return events.finish();
}

}  // namespace causal::ingest
