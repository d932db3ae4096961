#pragma once
// The line-based side files a bake takes beside the scene (--lightmap-scales, --realtime-lights):
// '#' starts a comment, blank lines are skipped, and each line's content is trimmed.
#include <optional>
#include <sstream>
#include <string>

#include "core/diagnostics.h"
#include "core/regular_file.h"

namespace radbake {

inline std::string trimSpaces(const std::string& s) {
    const size_t begin = s.find_first_not_of(" \t\r");
    if (begin == std::string::npos) return {};
    return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

// f(line number from 1, content without comment and surrounding blanks, the raw line) for each
// line with content.
template <class F>
void forEachSideFileLine(const std::string& text, F&& f) {
    std::istringstream in(text);
    std::string raw;
    for (int line = 1; std::getline(in, raw); ++line) {
        const std::string content = trimSpaces(raw.substr(0, raw.find('#')));
        if (!content.empty()) f(line, content, raw);
    }
}

// The file's text, or nullopt after an error naming `what` (a folder would read as nothing, a
// FIFO block the bake: only regular files are read).
inline std::optional<std::string> readSideFile(const std::string& path, const std::string& what, Diagnostics& diagnostics) {
    std::string why;
    std::optional<std::string> text = readRegularFile(path, why);
    if (!text) diagnostics.error({path, 0, 0}, "cannot open " + what + ": " + why);
    return text;
}

}  // namespace radbake
