// One field list per checkpointed structure serves both directions, so what restore reads is what save wrote,
// field for field, by construction (no second list to keep in step). A field list is a template
// `fields(io, x)` over the direction: Put (save) writes every field, Get (restore) reads it back.
#pragma once

#include "causal/estimation/state_archive.hpp"

namespace causal::alarms::detail {

struct Put {
  causal::StateWriter& out;
  template <class T>
  void operator()(const T& value) { out.put(value); }
  template <class T>
  void object(const T& value) { value.save(out); }  // a type with its own save() / restore()
  template <class T>
  void section(const T& value) { save(out, value); }  // a type with free save() / restore() (found by ADL)
};

struct Get {
  causal::StateReader& in;
  template <class T>
  void operator()(T& value) { in.read(value); }
  template <class T>
  void object(T& value) { value.restore(in); }
  template <class T>
  void section(T& value) { restore(in, value); }
};

}  // namespace causal::alarms::detail
