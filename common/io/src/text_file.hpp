// Internal: whole-file reading (plain or gzip) for the causal_io readers.
#pragma once

#include <string>

namespace causal::io::detail {

// Returns the file's bytes; gzip content (magic 1f 8b, any name) is decompressed, including multi-member
// streams. Throws InputError(path, 0, ...) if the file is missing, not a regular file, unreadable, or a
// corrupt/truncated gzip stream. The path "-" reads standard input to its end (so every reader takes `-`).
std::string read_text_file(const std::string& path);

}  // namespace causal::io::detail
