#pragma once
// SHA-256 of bake outputs, for manifest.json (the only user of OpenSSL, in hash.cpp).
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "core/diagnostics.h"

namespace radbake {

// The SHA-256 of `bytes` as 64 lower-case hex digits.
std::string sha256Hex(std::string_view bytes);

// The SHA-256 of a file's contents, read in blocks (a lightmap atlas need not fit in memory
// twice). Empty after reporting an I/O error located at the file.
std::optional<std::string> sha256File(const std::filesystem::path& path, Diagnostics& diagnostics);

}  // namespace radbake
