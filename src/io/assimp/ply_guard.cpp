// Assimp 5.2.5's PLY importer reads past its buffer, or loops for ever, on a header that does
// not end (fuzz_assimp_ply). Such files are refused here, before Assimp opens them.
#include "io/assimp/ply_guard.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>

namespace radbake {
namespace {

constexpr size_t kPlyEndLength = 10;  // "end_header"

// What may follow `end_header` for Assimp to end the header there: a blank, or a line end it
// reads safely. Its token match takes '\v' for part of the token (the header never ends: a
// hang, or a SEGV on a binary body), and its line reader, having stopped at '\f' or '\0',
// scans on for a '\n' that may not be there.
bool endsPlyHeader(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// The file's line and column of head[at] (head is the file after its 3-byte magic "ply").
SourceLocation plyLocation(const std::string& path, const std::string& head, size_t at) {
    const size_t line_start = at == 0 ? std::string::npos : head.rfind('\n', at - 1);
    const size_t column = line_start == std::string::npos ? at + 4 : at - line_start;
    return {path, static_cast<int>(1 + std::count(head.begin(), head.begin() + static_cast<std::ptrdiff_t>(at), '\n')),
            static_cast<int>(column)};
}

std::string byteName(char c) {
    char text[16];
    std::snprintf(text, sizeof text, "byte 0x%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
    return text;
}

}  // namespace

// Assimp 5.2.5's PLY importer runs past its buffer when the header never ends: a SEGV, or
// memory growing without bound (fuzz_assimp_ply, minimized: "ply\nformat binary_tm"). A file
// starting with "ply" (any case, as Assimp's magic check) must therefore have a line that is
// the token `end_header` within its first MiB; otherwise it is a located error here (at
// the byte after the token when that is white space Assimp misreads) and Assimp never sees it.
bool checkPlyInput(const std::string& path, Diagnostics& diagnostics) {
    constexpr size_t kMaxHeader = size_t(1) << 20;
    std::ifstream in(path, std::ios::binary);
    char magic[3] = {};
    in.read(magic, 3);
    if (in.gcount() < 3 || std::tolower(static_cast<unsigned char>(magic[0])) != 'p' ||
        std::tolower(static_cast<unsigned char>(magic[1])) != 'l' || std::tolower(static_cast<unsigned char>(magic[2])) != 'y')
        return true;  // not PLY: another importer, or Assimp refuses it cleanly
    std::string head(kMaxHeader, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<size_t>(in.gcount()));
    size_t bad_end = std::string::npos;  // the first `end_header` followed by white space Assimp misreads
    for (size_t at = head.find('\n'); at != std::string::npos; at = head.find('\n', at + 1)) {
        const size_t first = head.find_first_not_of(" \t", at + 1);
        // The token alone: "end_headerat z" does not end the header, and an end_header that
        // is the file's last bytes hangs Assimp's line reader.
        if (first == std::string::npos || head.compare(first, kPlyEndLength, "end_header") != 0) continue;
        const size_t after = first + kPlyEndLength;
        if (after >= head.size()) continue;
        if (endsPlyHeader(head[after])) return true;
        if (std::isspace(static_cast<unsigned char>(head[after])) || head[after] == '\0')
            bad_end = std::min(bad_end, after);
    }
    if (bad_end != std::string::npos) {
        diagnostics.error(plyLocation(path, head, bad_end),
                          "PLY end_header is followed by " + byteName(head[bad_end]) +
                              ", not a space, tab or line end: the header would not end where it should");
        return false;
    }
    diagnostics.error({path, 1, 1}, head.size() == kMaxHeader ? "PLY header has no end_header line in its first MiB"
                                                              : "PLY header has no end_header line");
    return false;
}

}  // namespace radbake
