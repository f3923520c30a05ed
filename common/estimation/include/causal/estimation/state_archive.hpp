// A small, versioned binary archive for checkpointing the state of the streaming estimators, the alarm
// engine and the services (crash and restart safety: kill -9, restart, resume where it left off).
//
// Format: little-endian host doubles/integers written as raw bytes (checkpoints are read back by the same
// build on the same kind of machine; the file header carries a format version and the section tags catch a
// mismatch). Every object writes a tagged section: begin(tag, version) ... and the reader checks the tag
// and version with expect(tag, version), so a checkpoint from another build or of another object fails
// with a clear StateError instead of restoring garbage.
//
// Files: save_state_file() writes "<path>.tmp" and renames it over <path> (std::filesystem::rename is
// atomic on POSIX), so a process killed while saving leaves the previous checkpoint intact. A checksum
// (FNV-1a 64 over the payload) detects a torn or corrupted file. Data written before the rename survives a
// kill -9 (it is in the page cache); surviving a power loss would need fsync, which the standard library
// does not offer: the services document that bound.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace causal::estimation {

class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class StateWriter {
 public:
  void begin(const std::string& tag, std::uint32_t version) {
    put(tag);
    put(version);
  }
  template <typename T, typename = std::enable_if_t<std::is_arithmetic_v<T> || std::is_enum_v<T>>>
  void put(T value) {
    const char* p = reinterpret_cast<const char*>(&value);
    bytes_.append(p, sizeof(T));
  }
  void put(bool value) { put(static_cast<std::uint8_t>(value ? 1 : 0)); }
  void put(const std::string& s) {
    put(static_cast<std::uint64_t>(s.size()));
    bytes_.append(s);
  }
  void put(const char* s) { put(std::string(s)); }
  template <typename Scalar, int R, int C, int O, int MR, int MC>
  void put(const Eigen::Matrix<Scalar, R, C, O, MR, MC>& m) {
    put(static_cast<std::int64_t>(m.rows()));
    put(static_cast<std::int64_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      for (Eigen::Index i = 0; i < m.rows(); ++i) put(m(i, j));
  }
  template <typename T>
  void put(const std::vector<T>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    for (const auto& x : v) put(static_cast<const T&>(x));
  }
  void put(const std::vector<bool>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    for (bool x : v) put(x);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class StateReader {
 public:
  explicit StateReader(std::string bytes) : bytes_(std::move(bytes)) {}

  // Throws StateError unless the next section is `tag` at `version`.
  void expect(const std::string& tag, std::uint32_t version) {
    const std::string got = get<std::string>();
    if (got != tag) throw StateError("checkpoint: expected section '" + tag + "', found '" + got + "'");
    const auto v = get<std::uint32_t>();
    if (v != version) {
      throw StateError("checkpoint: section '" + tag + "' has version " + std::to_string(v) + ", this build reads " +
                       std::to_string(version));
    }
  }
  template <typename T>
  T get() {
    T value{};
    read(value);
    return value;
  }
  template <typename T>
  void read(T& value) {
    if constexpr (std::is_same_v<T, bool>) {
      value = get<std::uint8_t>() != 0;
    } else if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      need(sizeof(T));
      std::memcpy(&value, bytes_.data() + pos_, sizeof(T));
      pos_ += sizeof(T);
    } else if constexpr (std::is_same_v<T, std::string>) {
      const auto n = static_cast<std::size_t>(get<std::uint64_t>());
      need(n);
      value.assign(bytes_, pos_, n);
      pos_ += n;
    } else {
      read_other(value);
    }
  }
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  template <typename Scalar, int R, int C, int O, int MR, int MC>
  void read_other(Eigen::Matrix<Scalar, R, C, O, MR, MC>& m) {
    const auto rows = get<std::int64_t>();
    const auto cols = get<std::int64_t>();
    if (rows < 0 || cols < 0 || (R != Eigen::Dynamic && rows != R) || (C != Eigen::Dynamic && cols != C)) {
      throw StateError("checkpoint: matrix of invalid shape");
    }
    need(static_cast<std::size_t>(rows * cols) * sizeof(Scalar));
    m.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      for (Eigen::Index i = 0; i < m.rows(); ++i) read(m(i, j));
  }
  template <typename T>
  void read_other(std::vector<T>& v) {
    const auto n = static_cast<std::size_t>(get<std::uint64_t>());
    if (n > bytes_.size() - pos_) throw StateError("checkpoint: truncated (vector length)");
    v.clear();
    v.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      T x{};
      read(x);
      v.push_back(std::move(x));
    }
  }
  void read_other(std::vector<bool>& v) {
    const auto n = static_cast<std::size_t>(get<std::uint64_t>());
    if (n > bytes_.size() - pos_) throw StateError("checkpoint: truncated (vector length)");
    v.assign(n, false);
    for (std::size_t i = 0; i < n; ++i) v[i] = get<bool>();
  }
  void need(std::size_t n) const {
    if (n > bytes_.size() - pos_) throw StateError("checkpoint: truncated");
  }

  std::string bytes_;
  std::size_t pos_ = 0;
};

// Writes `payload` to `path` atomically (temporary file + rename) with a header (magic, format version,
// length, checksum). Throws StateError naming the path when it cannot be written.
void save_state_file(const std::string& path, const std::string& payload);
// The payload of a checkpoint written by save_state_file, or nullopt when `path` does not exist. Throws
// StateError naming the path when the file is unreadable, truncated, corrupted or of another format.
std::optional<std::string> load_state_file(const std::string& path);

}  // namespace causal::estimation
