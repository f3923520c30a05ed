// File-name component for an identifier chosen by somebody else (an asset group id from the bus).
#pragma once

#include <cstddef>
#include <string>

namespace causal::io {

// Letters, digits, '.', '-', '_' are kept, anything else becomes '_' (a leading '.' too: no hidden files, no
// ".."); when anything was replaced, "-" and 8 hex digits of a hash of the original follow, so two ids never
// share a file name. A component longer than kMaxFileComponentBytes (any name up to the name limit of
// name_limits.hpp can be) keeps its first bytes and ends in "-" and 16 hex digits of a 64-bit hash of the whole id,
// so that with a suffix and ".tmp" it still fits the file system's 255 bytes per file name.
inline constexpr std::size_t kMaxFileComponentBytes = 192;
std::string safe_file_component(const std::string& id);

}  // namespace causal::io
