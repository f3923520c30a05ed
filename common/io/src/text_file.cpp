#include "text_file.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <system_error>

#include "causal/io/input_error.hpp"

namespace causal::io::detail {
namespace {

bool has_gzip_magic(const std::string& bytes) {
  return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
         static_cast<unsigned char>(bytes[1]) == 0x8b;
}

// Inflates every gzip member in `in` (gzip allows concatenated members, e.g. `cat a.gz b.gz`).
std::string gunzip(const std::string& path, const std::string& in) {
  std::string out;
  // The gzip trailer's ISIZE (last 4 bytes, little endian) is the uncompressed size mod 2^32 of the
  // last member: a good capacity hint for the usual single-member file. Capped against absurd values.
  std::size_t hint = in.size() * 4;
  if (in.size() >= 18) {
    const auto* t = reinterpret_cast<const unsigned char*>(in.data() + in.size() - 4);
    const std::size_t isize = t[0] | (t[1] << 8) | (static_cast<std::size_t>(t[2]) << 16) |
                              (static_cast<std::size_t>(t[3]) << 24);
    if (isize <= in.size() * 1032 + 1024) hint = std::max(hint, isize);  // deflate's max ratio is ~1032:1
  }
  out.reserve(hint + 1);
  z_stream zs{};
  // 16 + MAX_WBITS: expect a gzip header/trailer (checks CRC32 and length).
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) throw InputError(path, 0, "zlib initialisation failed");
  std::size_t consumed = 0;
  char chunk[1 << 16];
  int ret = Z_OK;
  while (true) {
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data() + consumed));
    zs.avail_in = static_cast<uInt>(in.size() - consumed);
    zs.next_out = reinterpret_cast<Bytef*>(chunk);
    zs.avail_out = sizeof(chunk);
    ret = inflate(&zs, Z_NO_FLUSH);
    out.append(chunk, sizeof(chunk) - zs.avail_out);
    consumed = in.size() - zs.avail_in;
    if (ret == Z_STREAM_END) {
      // Another member follows? (Trailing zero padding is tolerated, like gzip -d does.)
      std::size_t k = consumed;
      while (k < in.size() && in[k] == '\0') ++k;
      if (k >= in.size()) break;
      consumed = k;
      if (inflateReset(&zs) != Z_OK) break;
      continue;
    }
    if (ret == Z_OK) continue;
    if (ret == Z_BUF_ERROR && zs.avail_in == 0) {
      inflateEnd(&zs);
      throw InputError(path, 0, "truncated gzip stream (unexpected end of file)");
    }
    const std::string msg = zs.msg ? zs.msg : ("zlib error " + std::to_string(ret));
    inflateEnd(&zs);
    throw InputError(path, 0, "corrupt gzip stream: " + msg);
  }
  inflateEnd(&zs);
  return out;
}

}  // namespace

std::string read_text_file(const std::string& path) {
  if (path == "-") {
    // Standard input: the whole stream (a pipe has no size to seek to), gzip allowed like a file.
    std::string bytes{std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>()};
    if (std::cin.bad()) throw InputError("<stdin>", 0, "read error");
    if (has_gzip_magic(bytes)) return gunzip("<stdin>", bytes);
    return bytes;
  }
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw InputError(path, 0, "file does not exist");
  if (!fs::is_regular_file(st)) throw InputError(path, 0, "not a regular file");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string bytes;
  f.seekg(0, std::ios::end);
  const std::streamoff size = f.tellg();
  f.seekg(0, std::ios::beg);
  if (size > 0) {
    bytes.resize(static_cast<std::size_t>(size));
    f.read(bytes.data(), size);
    if (f.gcount() != size) throw InputError(path, 0, "read error (file changed while reading?)");
  }
  if (has_gzip_magic(bytes)) return gunzip(path, bytes);
  return bytes;
}

}  // namespace causal::io::detail
