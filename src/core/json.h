#pragma once
#include <string>
#include <string_view>

namespace radbake {

// A JSON string literal, quotes included, with control characters, quotes and backslashes escaped.
std::string jsonString(std::string_view text);

}  // namespace radbake
