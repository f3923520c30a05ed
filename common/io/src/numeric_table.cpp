#include "causal/io/numeric_table.hpp"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <thread>

#include "causal/io/input_error.hpp"

namespace causal::io {
namespace {

constexpr char kMagic[8] = {'C', 'D', 'T', 'C', 'O', 'L', 'S', '1'};
constexpr std::size_t kFixedHeader = 48;  // magic + 5 x 64-bit fields
// Longest shortest-round-trip double ("-2.2250738585072014e-308" is 24) with room to spare.
constexpr std::size_t kMaxNumberChars = 32;
constexpr std::size_t kFlushBytes = std::size_t{1} << 20;

bool host_is_little_endian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

template <typename T>
void put_le(std::string& buf, T v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (!host_is_little_endian()) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  }
  buf.append(reinterpret_cast<const char*>(b), sizeof(T));
}

template <typename T>
T get_le(const unsigned char* b) {
  unsigned char tmp[sizeof(T)];
  std::memcpy(tmp, b, sizeof(T));
  if (!host_is_little_endian()) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(tmp[i], tmp[sizeof(T) - 1 - i]);
  }
  T v;
  std::memcpy(&v, tmp, sizeof(T));
  return v;
}

void check_columns(const NumericTableView& t) {
  if (t.rows < 0) throw std::invalid_argument("numeric table: negative row count");
  for (const ColumnView& c : t.columns) {
    if (c.values == nullptr && t.rows > 0) {
      throw std::invalid_argument("numeric table: column '" + c.name + "' has no values");
    }
  }
}

void write_all(std::ostream& out, const char* data, std::size_t n) {
  out.write(data, static_cast<std::streamsize>(n));
  if (!out) throw std::runtime_error("numeric table: write failed");
}

// Rows [lo, hi) as CSV text appended to `text`.
void format_rows(const NumericTableView& t, Eigen::Index lo, Eigen::Index hi, std::string& text) {
  const std::size_t row_max = (t.columns.size() + 1) * (kMaxNumberChars + 1) + 1;
  text.resize(static_cast<std::size_t>(hi - lo) * row_max);
  char* p = text.data();
  std::int64_t n = t.index_start + lo * t.index_step;
  for (Eigen::Index i = lo; i < hi; ++i, n += t.index_step) {
    p = std::to_chars(p, p + kMaxNumberChars, n).ptr;
    for (const ColumnView& c : t.columns) {
      *p++ = ',';
      p = std::to_chars(p, p + kMaxNumberChars, c.values[i]).ptr;
    }
    *p++ = '\n';
  }
  text.resize(static_cast<std::size_t>(p - text.data()));
}

}  // namespace

void write_numeric_csv(std::ostream& out, const NumericTableView& t, int threads) {
  check_columns(t);
  std::string header = t.index_name;
  for (const ColumnView& c : t.columns) header += "," + c.name;
  header += "\n";
  write_all(out, header.data(), header.size());

  // Blocks of rows small enough to stay around 1 MiB of text each; with several threads, one block per thread
  // is formatted at a time and the blocks are written in order (the text does not depend on `threads`).
  const std::size_t row_max = (t.columns.size() + 1) * (kMaxNumberChars + 1) + 1;
  const Eigen::Index block = std::max<Eigen::Index>(1, static_cast<Eigen::Index>(kFlushBytes / row_max));
  const int workers = std::max(1, threads);
  std::vector<std::string> text(static_cast<std::size_t>(workers));
  for (Eigen::Index lo = 0; lo < t.rows; lo += block * workers) {
    std::vector<std::thread> helpers;
    for (int w = 1; w < workers && lo + w * block < t.rows; ++w) {
      const Eigen::Index a = lo + w * block, b = std::min(t.rows, a + block);
      helpers.emplace_back([&t, a, b, &slot = text[static_cast<std::size_t>(w)]] { format_rows(t, a, b, slot); });
    }
    format_rows(t, lo, std::min(t.rows, lo + block), text[0]);
    for (std::thread& h : helpers) h.join();
    for (std::size_t w = 0; w <= helpers.size(); ++w) write_all(out, text[w].data(), text[w].size());
  }
}

void write_numeric_columns(std::ostream& out, const NumericTableView& t) {
  check_columns(t);
  std::string names;
  auto put_name = [&names](const std::string& s) {
    if (s.size() > std::numeric_limits<std::uint32_t>::max()) throw std::invalid_argument("column name too long");
    put_le(names, static_cast<std::uint32_t>(s.size()));
    names += s;
  };
  put_name(t.index_name);
  for (const ColumnView& c : t.columns) put_name(c.name);
  const std::size_t data_offset = (kFixedHeader + names.size() + 7) / 8 * 8;

  std::string header(kMagic, sizeof kMagic);
  put_le(header, static_cast<std::uint64_t>(t.rows));
  put_le(header, static_cast<std::uint64_t>(t.columns.size()));
  put_le(header, t.index_start);
  put_le(header, t.index_step);
  put_le(header, static_cast<std::uint64_t>(data_offset));
  header += names;
  header.resize(data_offset, '\0');
  write_all(out, header.data(), header.size());

  const auto rows = static_cast<std::size_t>(t.rows);
  if (host_is_little_endian()) {  // the columns are already the file's bytes
    for (const ColumnView& c : t.columns) write_all(out, reinterpret_cast<const char*>(c.values), rows * 8);
    return;
  }
  std::string buf;
  for (const ColumnView& c : t.columns) {
    buf.clear();
    for (std::size_t i = 0; i < rows; ++i) put_le(buf, c.values[i]);
    write_all(out, buf.data(), buf.size());
  }
}

NumericTable read_numeric_columns(const std::string& path) {
  std::ifstream file;
  if (path != "-") {
    file.open(path, std::ios::binary);
    if (!file) throw InputError(path, 0, "cannot open file");
  }
  std::istream& in = path == "-" ? std::cin : file;
  auto read_exact = [&](void* dst, std::size_t n, const char* what) {
    in.read(static_cast<char*>(dst), static_cast<std::streamsize>(n));
    if (static_cast<std::size_t>(in.gcount()) != n) {
      throw InputError(path, 0, std::string("truncated column file (") + what + ")");
    }
  };
  unsigned char fixed[kFixedHeader];
  read_exact(fixed, kFixedHeader, "header");
  if (std::memcmp(fixed, kMagic, sizeof kMagic) != 0) {
    throw InputError(path, 0, "not a column file (magic number is not CDTCOLS1)");
  }
  const auto rows = get_le<std::uint64_t>(fixed + 8);
  const auto cols = get_le<std::uint64_t>(fixed + 16);
  NumericTable t;
  t.index_start = get_le<std::int64_t>(fixed + 24);
  t.index_step = get_le<std::int64_t>(fixed + 32);
  const auto data_offset = get_le<std::uint64_t>(fixed + 40);
  // Bounds that keep every size below computable without overflow (2^40 values is 8 TB of data).
  constexpr std::uint64_t kMaxValues = std::uint64_t{1} << 40;
  if (cols > (1u << 24) || (cols > 0 && rows > kMaxValues / cols) || data_offset % 8 != 0 ||
      data_offset < kFixedHeader || data_offset > kFixedHeader + (cols + 1) * (4 + (std::uint64_t{1} << 16))) {
    throw InputError(path, 0, "column file header is inconsistent (rows " + std::to_string(rows) + ", columns " +
                                  std::to_string(cols) + ", data offset " + std::to_string(data_offset) + ")");
  }
  std::string names(static_cast<std::size_t>(data_offset - kFixedHeader), '\0');
  read_exact(names.data(), names.size(), "column names");
  std::size_t at = 0;
  for (std::uint64_t c = 0; c <= cols; ++c) {
    if (at + 4 > names.size()) throw InputError(path, 0, "column file header is inconsistent (names)");
    const auto len = get_le<std::uint32_t>(reinterpret_cast<const unsigned char*>(names.data()) + at);
    at += 4;
    if (len > names.size() - at) throw InputError(path, 0, "column file header is inconsistent (names)");
    std::string name = names.substr(at, len);
    at += len;
    if (c == 0) {
      t.index_name = std::move(name);
    } else {
      t.names.push_back(std::move(name));
    }
  }
  t.values.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  read_exact(t.values.data(), static_cast<std::size_t>(rows * cols * 8), "data");
  if (!host_is_little_endian()) {
    auto* b = reinterpret_cast<unsigned char*>(t.values.data());
    for (Eigen::Index i = 0; i < t.values.size(); ++i) t.values.data()[i] = get_le<double>(b + 8 * i);
  }
  if (in.peek() != std::char_traits<char>::eof()) {
    throw InputError(path, 0, "column file is longer than its header says (" + std::to_string(rows) + " rows x " +
                                  std::to_string(cols) + " columns)");
  }
  return t;
}

}  // namespace causal::io
