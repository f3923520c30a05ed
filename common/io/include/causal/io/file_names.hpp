// File-name component for an identifier chosen by somebody else (an asset group id from the bus).
#pragma once

#include <string>

namespace causal::io {

// Letters, digits, '.', '-', '_' are kept, anything else becomes '_' (a leading '.' too: no hidden files, no
// ".."); when anything was replaced, "-" and 8 hex digits of a hash of the original follow, so two ids never
// share a file name.
std::string safe_file_component(const std::string& id);

}  // namespace causal::io
