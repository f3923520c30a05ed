// The checkpoint writer and reader by name only (defined in causal/estimation/state_archive.hpp): a header
// that declares save()/restore() members includes this, its .cpp includes state_archive.hpp.
#pragma once

namespace causal::estimation {
class StateWriter;
class StateReader;
}  // namespace causal::estimation
