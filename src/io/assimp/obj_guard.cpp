// Assimp 5.2.5's OBJ importer builds one aiMesh per material group and keeps the finished
// ones in a local list until all are done; when a later group names a vertex that is not
// there (or holds a one-vertex line) it throws and the finished meshes leak
// (fuzz_assimp_obj). Such files are refused here, before Assimp opens them. The check reads
// the statements as Assimp's parser does, since a different reading would miss some of them.
#include "io/assimp/obj_guard.h"

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string_view>

namespace radbake {
namespace {

bool isLineEnd(char c) { return c == '\r' || c == '\n' || c == '\0' || c == '\f'; }
bool isBlank(char c) { return c == ' ' || c == '\t'; }
bool isSpaceOrLineEnd(char c) { return isBlank(c) || isLineEnd(c); }

// The file's statements as Assimp's IOStreamBuffer::getNextDataLine(buffer, '\\') builds
// them: a backslash before a line end joins the next line, whose first byte is taken as it is.
class ObjStatements {
public:
    explicit ObjStatements(std::istream& in) : in_(in) {}

    // The next statement and the line it starts on; false at the end of the file.
    bool next(std::string& statement, int& line) {
        if (!has(0)) return false;
        statement.clear();
        line = line_;
        for (;;) {
            if (at(0) == '\\' && isLineEnd(at(1))) {
                advance();
                while (at(0) != '\n') advance();
                advance();
            } else if (isLineEnd(at(0))) {
                break;
            }
            statement.push_back(at(0));
            advance();
            if (!has(0)) break;
        }
        advance();
        return true;
    }

private:
    // True when byte `k` past the current one is in the file.
    bool has(size_t k) {
        while (window_.size() <= offset_ + k && in_) {
            window_.erase(0, offset_);
            offset_ = 0;
            char chunk[1 << 16];
            in_.read(chunk, sizeof chunk);
            window_.append(chunk, static_cast<size_t>(in_.gcount()));
        }
        return window_.size() > offset_ + k;
    }
    // Past the end of the file Assimp's cache holds line feeds.
    char at(size_t k) { return has(k) ? window_[offset_ + k] : '\n'; }
    void advance() {
        if (!has(0)) return;
        if (window_[offset_] == '\n') ++line_;
        ++offset_;
    }

    std::istream& in_;
    std::string window_;
    size_t offset_ = 0;
    int line_ = 1;
};

// What the reading of a statement decided.
enum class Verdict { kReads, kRefused, kAssimpFails };

class ObjCheck {
public:
    ObjCheck(const std::string& path, Diagnostics& diagnostics) : path_(path), diagnostics_(diagnostics) {}

    Verdict statement(const std::string& statement, int line) {
        statement_ = &statement;
        text_ = std::string_view(statement);
        for (size_t i = 0; i < text_.size(); ++i) {
            if (!isLineEnd(text_[i])) continue;
            text_ = text_.substr(0, i);  // Assimp's handlers stop there
            break;
        }
        line_ = line;
        if (in_cstype_) {
            if (c(0) == 'e') in_cstype_ = firstWord() != "end";
            return Verdict::kReads;
        }
        switch (c(0)) {
        case 'v': return vertexStatement();
        case 'f':
        case 'l':
        case 'p': return faceStatement();
        case 'c': in_cstype_ = firstWord() == "cstype"; return Verdict::kReads;
        default: return Verdict::kReads;
        }
    }

    // After the last statement: every index must name a vertex of the file.
    bool indicesInRange() {
        if (!any_index_ || largest_index_ < vertices_) return true;
        refuse(largest_line_, "OBJ statement names vertex " + std::to_string(largest_written_) + ", but the file defines " +
                                  std::to_string(vertices_) + " vertices");
        return false;
    }

private:
    char c(size_t i) const { return i < text_.size() ? text_[i] : '\n'; }

    std::string_view firstWord() const {
        size_t end = 0;
        while (!isSpaceOrLineEnd(c(end))) ++end;
        return text_.substr(0, end);
    }

    Verdict refuse(int line, const std::string& message) {
        diagnostics_.error({path_, line, 1}, message);
        return Verdict::kRefused;
    }

    bool nanOrInf(size_t i) const {
        auto word = [&](const char* w) {
            for (size_t k = 0; k < 3; ++k)
                if (std::tolower(static_cast<unsigned char>(c(i + k))) != w[k]) return false;
            return true;
        };
        return word("nan") || word("inf");
    }

    // Assimp's getNumComponentsInDataDefinition from byte `i`: the tokens that start like a
    // number. Nothing when a backslash before the line end would take Assimp past the line.
    std::optional<size_t> components(size_t i) const {
        size_t count = 0;
        for (;;) {
            if (c(i) == '\\' && isLineEnd(c(i + 1))) return std::nullopt;
            while (isBlank(c(i))) ++i;
            if (isLineEnd(c(i))) break;
            const char first = c(i);
            const bool numeric = std::isdigit(static_cast<unsigned char>(first)) || first == '-' || first == '+' || nanOrInf(i);
            while (!isSpaceOrLineEnd(c(i))) ++i;
            if (numeric) ++count;
            while (isBlank(c(i))) ++i;
            if (isLineEnd(c(i))) break;
        }
        return count;
    }

    Verdict vertexStatement() {
        const char kind = c(1);
        if (kind == ' ' || kind == '\t') {
            const std::optional<size_t> count = components(1);
            if (!count) return refuse(line_, "OBJ vertex statement ends in a stray backslash");
            if (*count == 3 || *count == 4 || *count == 6) {
                if (vertices_ == uint32_t(INT_MAX)) return refuse(line_, "OBJ file defines more vertices than Assimp counts");
                ++vertices_;
            }
        } else if (kind == 't') {
            const std::optional<size_t> count = components(2);
            if (!count) return refuse(line_, "OBJ texture coordinate statement ends in a stray backslash");
            if (*count != 2 && *count != 3) return Verdict::kAssimpFails;  // "Invalid number of components"
            has_uv_ = true;
        } else if (kind == 'n') {
            has_normals_ = true;
        }
        return Verdict::kReads;
    }

    // Assimp's getFace: walks the bytes, '/' moving to the next part of a corner and a blank
    // to the next corner, and reads an index with atoi wherever it stands on anything else.
    Verdict faceStatement() {
        const char kind = c(0);
        size_t i = 0;
        while (!isSpaceOrLineEnd(c(i))) ++i;
        while (isBlank(c(i))) ++i;
        int part = 0;
        size_t corners = 0;
        for (;;) {
            const char here = c(i);
            size_t step = 1;
            if (isLineEnd(here)) break;
            if (here == '/') {
                ++part;
            } else if (isBlank(here)) {
                part = 0;
            } else {
                // atoi skips white space that is not a blank, past the line's end
                if (here == '\v') return refuse(line_, "OBJ statement holds a vertical tab");
                errno = 0;
                const long value = std::strtol(statement_->c_str() + i, nullptr, 10);
                if (errno == ERANGE || value > INT_MAX || value < INT_MIN)
                    return refuse(line_, "OBJ index is beyond the range of an int");
                const int index = static_cast<int>(value);
                if (index == 0) return Verdict::kAssimpFails;  // "Invalid face index"
                if (index < 0) ++step;
                for (int rest = index / 10; rest != 0; rest /= 10) ++step;
                if (part == 1 && !has_uv_ && has_normals_) part = 2;
                if (part > 2) return refuse(line_, "OBJ index has more than three parts (vertex/uv/normal)");
                if (part == 0) {
                    ++corners;
                    const uint32_t named = index > 0 ? uint32_t(index - 1) : uint32_t(int(vertices_) + index);
                    if (!any_index_ || named > largest_index_) {
                        largest_index_ = named;
                        largest_written_ = index;
                        largest_line_ = line_;
                    }
                    any_index_ = true;
                }
            }
            i += step;
        }
        if (kind == 'l' && corners == 1) return refuse(line_, "OBJ line statement has a single vertex: a line needs two");
        return Verdict::kReads;
    }

    const std::string& path_;
    Diagnostics& diagnostics_;
    const std::string* statement_ = nullptr;
    std::string_view text_;
    int line_ = 0;
    bool in_cstype_ = false;
    bool has_uv_ = false;
    bool has_normals_ = false;
    uint32_t vertices_ = 0;
    bool any_index_ = false;
    uint32_t largest_index_ = 0;
    int largest_written_ = 0;
    int largest_line_ = 0;
};

}  // namespace

bool checkObjInput(const std::string& path, size_t max_bytes, Diagnostics& diagnostics) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return true;  // the reader reports it
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0 || static_cast<uint64_t>(size) > max_bytes) return true;  // the reader refuses it
    in.seekg(0);
    ObjStatements statements(in);
    ObjCheck check(path, diagnostics);
    std::string statement;
    int line = 0;
    while (statements.next(statement, line)) {
        switch (check.statement(statement, line)) {
        case Verdict::kReads: break;
        case Verdict::kRefused: return false;
        case Verdict::kAssimpFails: return true;
        }
    }
    return check.indicesInRange();
}

}  // namespace radbake
