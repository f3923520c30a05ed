// Save and restore from one field list (checkpoints, state_archive.hpp).
#pragma once

#include "causal/estimation/state_archive.hpp"

namespace causal {

// One field list per structure can serve both directions, so what restore reads is what save wrote, field
// for field, by construction (no second list to keep in step): write it once as a template `fields(io, x)`
// and call it with SaveFields{writer} (x const) or RestoreFields{reader}. io(v) puts / reads one value,
// io.object(v) calls v.save / v.restore, io.section(v) the free save(out, v) / restore(in, v) of v's namespace.
struct SaveFields {
  StateWriter& out;
  template <class T>
  void operator()(const T& value) { out.put(value); }
  template <class T>
  void object(const T& value) { value.save(out); }
  template <class T>
  void section(const T& value) { save(out, value); }
};

struct RestoreFields {
  StateReader& in;
  template <class T>
  void operator()(T& value) { in.read(value); }
  template <class T>
  void object(T& value) { value.restore(in); }
  template <class T>
  void section(T& value) { restore(in, value); }
};

}  // namespace causal
