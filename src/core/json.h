#pragma once
#include <string>
#include <string_view>

namespace radbake {

// A JSON string literal, quotes included, with control characters, quotes and backslashes escaped.
// For `radbake info --json`'s one line; the export stage writes its files with nlohmann/json.
std::string jsonString(std::string_view text);

}  // namespace radbake
