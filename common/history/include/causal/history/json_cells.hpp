// The JSON-array cells of condition_vectors and factors (channel or factor names, and their values): one table
// holds every asset group whatever its channels. Written so that SQLite's json_extract and PostgreSQL's ::jsonb
// read them (docs/historian.md has queries); non-finite and empty values are JSON null.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace causal::history {

std::string json_string_array(const std::vector<std::string>& items);
// Cells as the CSV writes them: "" (unknown), "nan", "inf" -> null; numbers as written.
std::string json_number_array(const std::vector<std::string>& cells);
// Parse what the two functions above write; nullopt when the text is not such an array.
std::optional<std::vector<std::string>> parse_json_string_array(const std::string& text);
std::optional<std::vector<std::optional<double>>> parse_json_number_array(const std::string& text);

}  // namespace causal::history
