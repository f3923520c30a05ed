// Save and restore from one field list (checkpoints, state_archive.hpp).
#pragma once

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_checks.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace causal::estimation {

// One field list per structure can serve both directions, so what restore reads is what save wrote, field
// for field, by construction (no second list to keep in step): write it once as a template `fields(io, x)`
// and call it with SaveFields{writer} (x const) or RestoreFields{reader}. io(a, b, ...) puts / reads plain
// values in that order (one call for a run of fields, like an archive's `ar(a, b, c)`), io.object(v) calls
// v.save / v.restore, io.section(v) the free save(out, v) / restore(in, v) of v's namespace,
// io.tag(name, version) begins / expects the section, io.as<Stored>(v) stores v as the type Stored (a size_t
// count as std::uint64_t, an int as std::int32_t) and converts it back on restore.
// io.same(v, what, owner) stores a parameter the restoring object already has and, on restore, throws
// StateError unless the saved one equals it (expect_saved; io.same_as<Stored> stores it as Stored);
// io.same_size(v, what) stores a vector whose size follows from the object's shape and, on restore, refuses
// another size (read_same_size); io.same_count(n, what) stores a count the restoring object already has (the
// size of its channel list, say) and refuses another ("checkpoint: <what> count 3, expected 4").
// Io::restoring says which way the list runs, for the few checks and resizes only a restore needs. Restore
// into a copy and move it in at the end, so a damaged checkpoint leaves the object as it was.
struct SaveFields {
  static constexpr bool restoring = false;
  StateWriter& out;
  template <class... T>
  void operator()(const T&... values) { (out.put(values), ...); }
  void tag(const char* name, std::uint32_t version) { out.begin(name, version); }
  template <class Stored, class T>
  void as(const T& value) { out.put(static_cast<Stored>(value)); }
  template <class Stored, class T>
  void same_as(const T& value, const char*, const char*) { out.put(static_cast<Stored>(value)); }
  template <class T>
  void same(const T& value, const char*, const char*) { out.put(value); }
  void same_size(const std::vector<double>& values, const char*) { out.put(values); }
  void same_count(std::size_t count, const char*) { out.put(static_cast<std::uint64_t>(count)); }
  template <class T>
  void object(const T& value) { value.save(out); }
  template <class T>
  void section(const T& value) { save(out, value); }
};

struct RestoreFields {
  static constexpr bool restoring = true;
  StateReader& in;
  template <class... T>
  void operator()(T&... values) { (in.read(values), ...); }
  void tag(const char* name, std::uint32_t version) { in.expect(name, version); }
  template <class Stored, class T>
  void as(T& value) { value = static_cast<T>(in.get<Stored>()); }
  template <class Stored, class T>
  void same_as(const T& value, const char* what, const char* owner) {
    expect_saved(in, what, static_cast<Stored>(value), owner);
  }
  template <class T>
  void same(const T& value, const char* what, const char* owner) { expect_saved(in, what, value, owner); }
  void same_size(std::vector<double>& values, const char* what) { read_same_size(in, values, what); }
  void same_count(std::size_t count, const char* what) {
    const auto saved = in.get<std::uint64_t>();
    if (saved != count) {
      throw StateError(std::string("checkpoint: ") + what + " count " + std::to_string(saved) + ", expected " +
                       std::to_string(count));
    }
  }
  template <class T>
  void object(T& value) { value.restore(in); }
  template <class T>
  void section(T& value) { restore(in, value); }
};

}  // namespace causal::estimation
