#include "causal/estimation/state_archive.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace causal::estimation {

namespace {

constexpr char kMagic[8] = {'C', 'T', 'W', 'I', 'N', 'S', 'T', '1'};
constexpr std::uint32_t kFormatVersion = 1;

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

}  // namespace

void save_state_file(const std::string& path, const std::string& payload) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw StateError("cannot write checkpoint '" + tmp + "'");
    StateWriter header;
    header.put(kFormatVersion);
    header.put(static_cast<std::uint64_t>(payload.size()));
    header.put(fnv1a(payload));
    out.write(kMagic, sizeof kMagic);
    out.write(header.bytes().data(), static_cast<std::streamsize>(header.bytes().size()));
    out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    out.flush();
    if (!out) throw StateError("cannot write checkpoint '" + tmp + "' (disk full?)");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw StateError("cannot rename checkpoint '" + tmp + "' to '" + path + "': " + ec.message());
}

std::optional<std::string> load_state_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw StateError("cannot read checkpoint '" + path + "'");
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t header = sizeof kMagic + sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t);
  if (all.size() < header || all.compare(0, sizeof kMagic, kMagic, sizeof kMagic) != 0) {
    throw StateError("'" + path + "' is not a causal-twin checkpoint");
  }
  StateReader r(all.substr(sizeof kMagic, header - sizeof kMagic));
  const auto version = r.get<std::uint32_t>();
  const auto size = r.get<std::uint64_t>();
  const auto sum = r.get<std::uint64_t>();
  if (version != kFormatVersion) {
    throw StateError("checkpoint '" + path + "' has format " + std::to_string(version) + ", this build reads " +
                     std::to_string(kFormatVersion));
  }
  if (all.size() - header != size) throw StateError("checkpoint '" + path + "' is truncated");
  std::string payload = all.substr(header);
  if (fnv1a(payload) != sum) throw StateError("checkpoint '" + path + "' is corrupted (checksum mismatch)");
  return payload;
}

}  // namespace causal::estimation
