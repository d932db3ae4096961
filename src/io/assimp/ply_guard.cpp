// Assimp 5.2.5's PLY importer trusts its input: it reads past its buffer, or loops for ever,
// on a header that does not end, and allocates whatever an element count asks for
// (fuzz_assimp_ply, docs/fuzzing.md). Such files are refused here, before Assimp opens them.
// The header is read as that importer reads it, with Assimp's own token functions and the
// quirks of its line buffer, so that the counts checked are the ones Assimp will use.
#include "io/assimp/ply_guard.h"

#include <assimp/ParsingUtils.h>
#include <assimp/fast_atof.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string_view>
#include <vector>

namespace radbake {
namespace {

// ---------------------------------------------------------------------------------------
// Where things are in the file.

// Line and column (1-based) of byte `offset` of the file, counting '\n' as an editor does.
SourceLocation locateOffset(const std::string& path, std::ifstream& in, uint64_t offset) {
    in.clear();
    in.seekg(0);
    std::vector<char> block(size_t(1) << 16);
    int line = 1;
    uint64_t line_start = 0, at = 0;
    while (at < offset) {
        in.read(block.data(), static_cast<std::streamsize>(std::min<uint64_t>(block.size(), offset - at)));
        const size_t got = static_cast<size_t>(in.gcount());
        if (got == 0) break;
        for (size_t i = 0; i < got; ++i)
            if (block[i] == '\n') {
                ++line;
                line_start = at + i + 1;
            }
        at += got;
    }
    return {path, line, static_cast<int>(std::min<uint64_t>(offset - line_start + 1, 1u << 30))};
}

// A name or token from the file fit to quote in a message: at most 32 bytes, others escaped.
std::string printable(std::string_view text) {
    std::string out = "'";
    for (size_t i = 0; i < text.size() && i < 32; ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (std::isprint(c) && c != '\'' && c != '\\') {
            out += static_cast<char>(c);
        } else {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\x%02x", c);
            out += escaped;
        }
    }
    return out + (text.size() > 32 ? "...'" : "'");
}

std::string byteName(char c) {
    char text[16];
    std::snprintf(text, sizeof text, "byte 0x%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
    return text;
}

// ---------------------------------------------------------------------------------------
// The header must end (findings 2a to 2c).

constexpr size_t kPlyEndLength = 10;  // "end_header"
constexpr size_t kMaxHeader = size_t(1) << 20;

// What may follow `end_header` for Assimp to end the header there: a blank, or a line end it
// reads safely. Its token match takes '\v' for part of the token (the header never ends: a
// hang, or a SEGV on a binary body), and its line reader, having stopped at '\f' or '\0',
// scans on for a '\n' that may not be there.
bool endsPlyHeader(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Assimp 5.2.5's PLY importer runs past its buffer when the header never ends: a SEGV, or
// memory growing without bound (fuzz_assimp_ply, minimized: "ply\nformat binary_tm"). The
// file must therefore have, within the MiB after its magic `ply` (at `magic`), a line that is
// the token `end_header`; otherwise it is a located error here (at the byte after the token
// when that is white space Assimp misreads).
bool checkHeaderEnds(const std::string& path, std::ifstream& in, uint64_t magic, Diagnostics& diagnostics) {
    std::string head(kMaxHeader, '\0');
    in.clear();
    in.seekg(static_cast<std::streamoff>(magic + 3));
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
        diagnostics.error(locateOffset(path, in, magic + 3 + bad_end),
                          "PLY end_header is followed by " + byteName(head[bad_end]) +
                              ", not a space, tab or line end: the header would not end where it should");
        return false;
    }
    diagnostics.error(locateOffset(path, in, magic), head.size() == kMaxHeader
                                                         ? "PLY header has no end_header line in its first MiB"
                                                         : "PLY header has no end_header line");
    return false;
}

// ---------------------------------------------------------------------------------------
// Assimp's reading of the file, as PLYImporter::InternReadFile and PLY::DOM do it.

constexpr size_t kAssimpBlock = size_t(1) << 20;  // the importer's IOStreamBuffer block

// Assimp's line buffer: a std::vector<char> that each line read resizes to the block size
// and overwrites from the front, so bytes of an earlier, longer line stay behind the current
// one, and that the header parser shortens from the front as it consumes tokens. Here a window
// into `store_`, so shortening costs nothing; a '\0' always follows the window.
class LineBuffer {
public:
    char* data() { return store_.data() + begin_; }
    size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    // Bytes dropped from the front since the current line was read.
    size_t consumed() const { return consumed_; }

    void erase(size_t count) {
        count = std::min(count, size_);
        begin_ += count;
        size_ -= count;
        consumed_ += count;
    }
    // std::vector::resize: new bytes are zero.
    void resize(size_t size) {
        if (begin_ + size + 1 > store_.size()) {
            std::memmove(store_.data(), data(), size_);
            begin_ = 0;
            if (size + 1 > store_.size()) store_.resize(2 * (size + 1));
        }
        if (size > size_) std::fill(data() + size_, data() + size, '\0');
        size_ = size;
        data()[size_] = '\0';
    }
    void startLine() { consumed_ = 0; }

private:
    std::vector<char> store_ = std::vector<char>(1, '\0');
    size_t begin_ = 0, size_ = 0, consumed_ = 0;
};

// Assimp's IOStreamBuffer<char> over the file: blocks of 1 MiB (the whole file when smaller)
// in a cache that starts out filled with '\n' and keeps an earlier block's bytes past a short
// last one. overrun() is set when Assimp would read outside the file's bytes.
class AssimpStream {
public:
    AssimpStream(std::ifstream& in, uint64_t size)
        : in_(in), cache_(kAssimpBlock, '\n'), cache_size_(static_cast<size_t>(std::min<uint64_t>(size, kAssimpBlock))) {}

    // IOStreamBuffer::getNextLine: false at the end of the file, possibly after part of a
    // line (Assimp ignores that result and parses what the buffer holds).
    bool nextLine(LineBuffer& buffer) {
        buffer.resize(cache_size_);
        buffer.startLine();
        line_start_ = position();
        line_length_ = 0;
        delivered_ = false;
        if (cache_pos_ == cache_size_ || file_pos_ == 0) {
            if (!readBlock()) return false;
        }
        if (cache_pos_ > cache_size_) return overran();
        if (Assimp::IsLineEnd(cache_[cache_pos_])) {
            while (cache_[cache_pos_] != '\n')
                if (++cache_pos_ >= cache_.size()) return overran();
            ++cache_pos_;
            if (cache_pos_ == cache_size_ && !readBlock()) return false;
            if (cache_pos_ > cache_size_) return overran();
        }
        line_start_ = position();
        size_t i = 0;
        while (!Assimp::IsLineEnd(cache_[cache_pos_])) {
            buffer.data()[i] = cache_[cache_pos_];
            ++cache_pos_;
            ++i;
            delivered_ = true;
            if (i == buffer.size()) buffer.resize(buffer.size() * 2);
            if (cache_pos_ >= cache_size_) {
                line_length_ = i;
                if (!readBlock()) return false;
            }
        }
        buffer.data()[i] = '\n';
        ++cache_pos_;
        line_length_ = i;
        delivered_ = true;
        return true;
    }

    // Whether the last nextLine put a line, or the start of one, in the buffer.
    bool delivered() const { return delivered_ && !overrun_; }

    // The file offset of the next byte Assimp reads.
    uint64_t position() const { return file_pos_ == 0 ? 0 : file_pos_ - cache_size_ + cache_pos_; }
    bool overrun() const { return overrun_; }
    // The cache byte at the position, which may be past the file's bytes.
    char peek() const { return cache_pos_ < cache_.size() ? cache_[cache_pos_] : '\0'; }
    size_t cachePos() const { return cache_pos_; }
    size_t cacheSize() const { return cache_size_; }

    // The file offset of `buffer`'s first byte when it is still part of the line last read,
    // else of that line's start (the parser is reading what an earlier line left behind).
    uint64_t offsetOf(const LineBuffer& buffer) const {
        return buffer.consumed() < line_length_ ? line_start_ + buffer.consumed() : line_start_;
    }
    uint64_t offsetOf(const LineBuffer& buffer, const char* at, const char* start) const {
        const size_t index = buffer.consumed() + static_cast<size_t>(at - start);
        return index < line_length_ ? line_start_ + index : line_start_;
    }

private:
    bool readBlock() {
        in_.clear();
        in_.seekg(static_cast<std::streamoff>(file_pos_));
        in_.read(cache_.data(), static_cast<std::streamsize>(cache_size_));
        const size_t got = static_cast<size_t>(std::max<std::streamsize>(in_.gcount(), 0));
        if (got == 0) return false;
        cache_size_ = std::min(cache_size_, got);
        file_pos_ += cache_size_;
        cache_pos_ = 0;
        return true;
    }
    bool overran() {
        overrun_ = true;
        return false;
    }

    std::ifstream& in_;
    std::vector<char> cache_;
    size_t cache_size_;
    size_t cache_pos_ = 0;
    uint64_t file_pos_ = 0;
    uint64_t line_start_ = 0;
    size_t line_length_ = 0;
    bool delivered_ = false;
    bool overrun_ = false;
};

// PLY::DOM's helpers: one of Assimp's token functions on the buffer, which then drops the
// bytes it passed.
template <class Step>
bool onBuffer(LineBuffer& buffer, Step step) {
    if (buffer.empty()) return false;
    const char* start = buffer.data();
    const char* at = start;
    const bool result = step(at);
    buffer.erase(static_cast<size_t>(at - start));
    return result;
}
bool skipSpaces(LineBuffer& b) {
    return onBuffer(b, [](const char*& at) { return Assimp::SkipSpaces(&at); });
}
bool skipLine(LineBuffer& b) {
    return onBuffer(b, [](const char*& at) { return Assimp::SkipLine(&at); });
}
bool skipSpacesAndLineEnd(LineBuffer& b) {
    return onBuffer(b, [](const char*& at) { return Assimp::SkipSpacesAndLineEnd(&at); });
}
bool tokenMatch(LineBuffer& b, const char* token) {
    return onBuffer(b, [token](const char*& at) {
        return Assimp::TokenMatch(at, token, static_cast<unsigned>(std::strlen(token)));
    });
}

// The token at the front of the buffer (up to a blank or line end), for messages.
std::string_view frontToken(LineBuffer& b) {
    const char* start = b.data();
    const char* end = start;
    while (!Assimp::IsSpaceOrNewLine(*end)) ++end;
    return {start, static_cast<size_t>(end - start)};
}

// PLY::DOM::SkipComments: a `comment` line is dropped unless it names a TextureFile. Assimp
// then parses whatever follows in the buffer, which may be what an earlier line left there.
bool skipComments(LineBuffer& b) {
    if (b.empty()) return false;
    const char* start = b.data();
    const char* at = start;
    if (!Assimp::SkipSpaces(&at) || !Assimp::TokenMatch(at, "comment", 7)) return false;
    if (!Assimp::SkipSpaces(&at)) Assimp::SkipLine(&at);
    if (Assimp::TokenMatch(at, "TextureFile", 11)) return true;
    Assimp::SkipLine(&at);
    b.erase(static_cast<size_t>(at - start));
    return true;
}

enum class PlyType { Invalid, Char, UChar, Short, UShort, Int, UInt, Float, Double };

size_t binarySize(PlyType type) {
    switch (type) {
    case PlyType::Char:
    case PlyType::UChar: return 1;
    case PlyType::Short:
    case PlyType::UShort: return 2;
    case PlyType::Int:
    case PlyType::UInt:
    case PlyType::Float: return 4;
    case PlyType::Double: return 8;
    case PlyType::Invalid: break;
    }
    return 0;
}

// PLY::Property::ParseDataType, in its order.
PlyType dataType(LineBuffer& b) {
    static constexpr std::pair<const char*, PlyType> kTypes[] = {
        {"char", PlyType::Char},     {"int8", PlyType::Char},      {"uchar", PlyType::UChar},
        {"uint8", PlyType::UChar},   {"short", PlyType::Short},    {"int16", PlyType::Short},
        {"ushort", PlyType::UShort}, {"uint16", PlyType::UShort},  {"int32", PlyType::Int},
        {"int", PlyType::Int},       {"uint32", PlyType::UInt},    {"uint", PlyType::UInt},
        {"float", PlyType::Float},   {"float32", PlyType::Float},  {"double64", PlyType::Double},
        {"double", PlyType::Double}, {"float64", PlyType::Double}};
    for (const auto& [token, type] : kTypes)
        if (tokenMatch(b, token)) return type;
    return PlyType::Invalid;
}

// The property semantics the checks need; Assimp knows more (colours, normals, ...).
enum class PropertyUse { Other, VertexIndex, TextureCoordinates, Opacity, PhongPower, Unknown };

// PLY::Property::ParseSemantic: consumes a known name, or the rest of the line.
PropertyUse propertySemantic(LineBuffer& b) {
    static constexpr std::pair<const char*, PropertyUse> kNames[] = {
        {"red", PropertyUse::Other},           {"green", PropertyUse::Other},
        {"blue", PropertyUse::Other},          {"alpha", PropertyUse::Other},
        {"vertex_index", PropertyUse::VertexIndex}, {"vertex_indices", PropertyUse::VertexIndex},
        {"texcoord", PropertyUse::TextureCoordinates}, {"material_index", PropertyUse::Other},
        {"ambient_red", PropertyUse::Other},   {"ambient_green", PropertyUse::Other},
        {"ambient_blue", PropertyUse::Other},  {"ambient_alpha", PropertyUse::Other},
        {"diffuse_red", PropertyUse::Other},   {"diffuse_green", PropertyUse::Other},
        {"diffuse_blue", PropertyUse::Other},  {"diffuse_alpha", PropertyUse::Other},
        {"specular_red", PropertyUse::Other},  {"specular_green", PropertyUse::Other},
        {"specular_blue", PropertyUse::Other}, {"specular_alpha", PropertyUse::Other},
        {"opacity", PropertyUse::Opacity},     {"specular_power", PropertyUse::PhongPower},
        {"r", PropertyUse::Other},             {"g", PropertyUse::Other},
        {"b", PropertyUse::Other},             {"u", PropertyUse::Other},
        {"s", PropertyUse::Other},             {"tx", PropertyUse::Other},
        {"texture_u", PropertyUse::Other},     {"v", PropertyUse::Other},
        {"t", PropertyUse::Other},             {"ty", PropertyUse::Other},
        {"texture_v", PropertyUse::Other},     {"x", PropertyUse::Other},
        {"y", PropertyUse::Other},             {"z", PropertyUse::Other},
        {"nx", PropertyUse::Other},            {"ny", PropertyUse::Other},
        {"nz", PropertyUse::Other}};
    for (const auto& [name, use] : kNames)
        if (tokenMatch(b, name)) return use;
    skipLine(b);
    return PropertyUse::Unknown;
}

struct PlyProperty {
    bool list = false;
    PlyType count_type = PlyType::Invalid;  // of a list's length
    PlyType type = PlyType::Invalid;        // of the value, or of a list's entries
    PropertyUse use = PropertyUse::Other;
    std::string name;
};

// PLY::Property::ParseProperty.
bool parseProperty(LineBuffer& b, PlyProperty& property) {
    if (!skipSpaces(b) || !tokenMatch(b, "property") || !skipSpaces(b)) return false;
    if (tokenMatch(b, "list")) {
        property.list = true;
        if ((property.count_type = dataType(b)) == PlyType::Invalid) {
            skipLine(b);
            return false;
        }
        if (!skipSpaces(b)) return false;
    }
    if ((property.type = dataType(b)) == PlyType::Invalid) {
        skipLine(b);
        return false;
    }
    if (!skipSpaces(b)) return false;
    property.name = frontToken(b);
    property.use = propertySemantic(b);
    skipSpacesAndLineEnd(b);
    return true;
}

enum class ElementKind { Other, Vertex, Face, TriStrip, Edge, Material, TextureFile };

struct PlyElement {
    ElementKind kind = ElementKind::Other;
    std::string name;        // as written (an unknown element's first token)
    uint32_t count = 0;      // NumOccur, as Assimp computes it
    std::string count_text;  // the digits Assimp read it from
    uint64_t offset = 0;     // in the file, of its `element` token
    std::vector<PlyProperty> properties;
};

// PLY::Element::ParseElement. Assimp reads the count with strtoul10, which stops at the first
// byte that is not a digit and wraps modulo 2^32; for an element it does not know, it reads
// the count from the start of the element's name (the name is not skipped).
bool parseElement(AssimpStream& stream, LineBuffer& b, PlyElement& element) {
    if (!skipSpaces(b)) return false;
    element.offset = stream.offsetOf(b);
    if (!tokenMatch(b, "element") && !tokenMatch(b, "comment")) return false;
    if (!skipSpaces(b)) return false;
    static constexpr std::pair<const char*, ElementKind> kKinds[] = {
        {"vertex", ElementKind::Vertex}, {"face", ElementKind::Face},         {"tristrips", ElementKind::TriStrip},
        {"edge", ElementKind::Edge},     {"material", ElementKind::Material}, {"TextureFile", ElementKind::TextureFile}};
    element.name = frontToken(b);
    for (const auto& [token, kind] : kKinds)
        if (tokenMatch(b, token)) {
            element.kind = kind;
            break;
        }
    if (!skipSpaces(b)) return false;
    if (element.kind == ElementKind::TextureFile) {
        skipSpacesAndLineEnd(b);
        return true;
    }
    const char* digits = b.data();
    const char* end = digits;
    element.count = Assimp::strtoul10(digits, &end);
    element.count_text.assign(digits, static_cast<size_t>(end - digits));
    skipSpacesAndLineEnd(b);
    while (true) {
        stream.nextLine(b);
        skipComments(b);
        PlyProperty property;
        if (!parseProperty(b, property)) break;
        element.properties.push_back(std::move(property));
    }
    return true;
}

// PLY::DOM::ParseHeader. False where Assimp would loop for ever or read outside the file.
bool parseHeader(AssimpStream& stream, LineBuffer& b, std::vector<PlyElement>& elements) {
    while (!b.empty()) {
        skipComments(b);
        PlyElement element;
        if (parseElement(stream, b, element)) elements.push_back(std::move(element));
        else if (tokenMatch(b, "end_header")) return true;
        else if (!stream.nextLine(b)) return false;
        if (stream.overrun()) return false;
    }
    return false;
}

struct PlyHeader {
    bool binary = false;
    bool big_endian = false;
    std::vector<PlyElement> elements;
    uint64_t body = 0;  // file offset where Assimp starts reading the elements
};

enum class HeaderRead { Parsed, AssimpRefuses, NeverEnds };

// PLYImporter::InternReadFile up to the element data, after the magic line.
HeaderRead readHeader(AssimpStream& stream, LineBuffer& b, PlyHeader& header) {
    LineBuffer format_line;
    stream.nextLine(format_line);
    const char* at = format_line.data();
    Assimp::SkipSpacesAndLineEnd(&at);
    if (!Assimp::TokenMatch(at, "format", 6)) return HeaderRead::AssimpRefuses;
    if (Assimp::TokenMatch(at, "ascii", 5)) {
        header.binary = false;
    } else if (std::strncmp(at, "binary_", 7) == 0) {
        header.binary = true;
        header.big_endian = at[7] == 'b' || at[7] == 'B';
    } else {
        return HeaderRead::AssimpRefuses;  // "Unknown file format", before it allocates
    }
    stream.nextLine(b);
    if (stream.overrun() || !parseHeader(stream, b, header.elements)) return HeaderRead::NeverEnds;
    header.body = stream.position();
    if (header.binary) {
        // PLY::DOM::ParseInstanceBinary takes the rest of the cache and drops a first '\n'
        // (the end of a CRLF). With the header ending a full block, that rest is empty and
        // Assimp reads its first byte anyway.
        if (stream.cachePos() == stream.cacheSize() && stream.cacheSize() == kAssimpBlock) return HeaderRead::NeverEnds;
        if (stream.peek() == '\n' && stream.cachePos() < stream.cacheSize()) ++header.body;
    } else {
        skipSpacesAndLineEnd(b);
    }
    return HeaderRead::Parsed;
}

// ---------------------------------------------------------------------------------------
// The checks.

std::string elementName(const PlyElement& element) { return printable(element.name); }

// Finding 5: PLYImporter::LoadVertex and LoadFace fill one vertex array and one face array,
// allocated for the first vertex element and the first face (or tristrips) element, at the
// instance's index within its own element. A second such element overwrites the first one's
// face index arrays (a leak) and writes past the arrays when it has more instances.
bool checkOneOfEach(const std::string& path, std::ifstream& in, const PlyHeader& header, Diagnostics& diagnostics) {
    const PlyElement* first_vertex = nullptr;
    const PlyElement* first_face = nullptr;
    for (const PlyElement& element : header.elements) {
        const bool vertex = element.kind == ElementKind::Vertex;
        const bool face = element.kind == ElementKind::Face || element.kind == ElementKind::TriStrip;
        if (!vertex && !face) continue;
        const PlyElement*& first = vertex ? first_vertex : first_face;
        if (first == nullptr) {
            first = &element;
            continue;
        }
        const std::string what = vertex ? "vertex" : "face";
        diagnostics.error(locateOffset(path, in, element.offset),
                          "PLY element " + elementName(element) + " is a second " + what + " element (the first, " +
                              elementName(*first) + ", is on line " +
                              std::to_string(locateOffset(path, in, first->offset).line) + "): Assimp 5.2.5 reads both into one " +
                              what + " array sized for the first, leaking or writing past it");
        return false;
    }
    return true;
}

// PLYImporter::LoadFace builds each triangle of a strip into the same face, leaking the
// indices of the one before: Assimp 5.2.5 keeps the last triangle of each strip. Strips are
// refused rather than read wrong.
bool checkNoStrips(const std::string& path, std::ifstream& in, const PlyHeader& header, Diagnostics& diagnostics) {
    for (const PlyElement& element : header.elements) {
        if (element.kind != ElementKind::TriStrip || element.count == 0) continue;
        diagnostics.error(locateOffset(path, in, element.offset),
                          "PLY element 'tristrips' is not read: Assimp 5.2.5 keeps only the last triangle of each "
                          "strip (and leaks the others); write the triangles as a face element");
        return false;
    }
    return true;
}

bool hasProperty(const PlyElement& element, PropertyUse use, bool list) {
    return std::any_of(element.properties.begin(), element.properties.end(),
                       [&](const PlyProperty& p) { return p.use == use && p.list == list; });
}

// Two properties Assimp 5.2.5 reads through others that may be missing (found reading
// PlyLoader.cpp): a face's texcoord list through its vertex_indices list (605; without one,
// through a null pointer: a SEGV), and the first material element's opacity at the index of
// its specular_power (857; without one the lookup throws after the mesh is built, which leaks).
bool checkPropertyPairs(const std::string& path, std::ifstream& in, const PlyHeader& header, Diagnostics& diagnostics) {
    bool first_material = true;
    for (const PlyElement& element : header.elements) {
        std::string problem;
        if (element.kind == ElementKind::Face && hasProperty(element, PropertyUse::TextureCoordinates, true) &&
            !hasProperty(element, PropertyUse::VertexIndex, true))
            problem = "has a texcoord list but no vertex_indices list: Assimp 5.2.5 reads the texture coordinates "
                      "through the missing indices (a crash)";
        if (element.kind == ElementKind::Material) {
            if (first_material && hasProperty(element, PropertyUse::Opacity, false) &&
                !hasProperty(element, PropertyUse::PhongPower, false))
                problem = "has an opacity but no specular_power property: Assimp 5.2.5 looks the opacity up at "
                          "specular_power's place, fails, and leaks the mesh";
            first_material = false;
        }
        if (problem.empty() || element.count == 0) continue;
        diagnostics.error(locateOffset(path, in, element.offset), "PLY element " + elementName(element) + " " + problem);
        return false;
    }
    return true;
}

// The smallest number of bytes one instance of `element` takes: in binary its fixed-size
// values and list lengths; in ASCII a token and a separator per property. At least one byte
// even with no properties, so that a count cannot outgrow the file.
uint64_t minimumInstanceBytes(const PlyElement& element, bool binary) {
    uint64_t bytes = 0;
    for (const PlyProperty& property : element.properties)
        bytes += binary ? binarySize(property.list ? property.count_type : property.type) : 2;
    return std::max<uint64_t>(bytes, 1);
}

// Finding 11: an element count larger than the bytes after the header could hold makes
// Assimp allocate for it or loop as many times.
bool checkCounts(const std::string& path, std::ifstream& in, const PlyHeader& header, uint64_t file_size,
                 Diagnostics& diagnostics) {
    const uint64_t bytes = file_size - std::min(file_size, header.body);
    // An ASCII file may end without a line end after its last value.
    const uint64_t room = header.binary ? bytes : bytes + 1;
    uint64_t total = 0, instances = 0;
    for (const PlyElement& element : header.elements) {
        if (element.kind == ElementKind::TextureFile) continue;
        const uint64_t unit = minimumInstanceBytes(element, header.binary);
        const uint64_t need = element.count * unit;
        total += need;
        instances += element.count;
        if (need <= room && total <= room) continue;
        std::string message = "PLY element " + elementName(element) + " declares " + std::to_string(element.count) +
                              " instances";
        if (element.count_text != std::to_string(element.count))
            message += " (Assimp 5.2.5 reads the count from " +
                       printable(element.count_text.empty() ? std::string_view("(no digits)") : element.count_text) +
                       (element.kind == ElementKind::Other ? ", the start of the element's name," : "") +
                       " modulo 2^32)";
        if (need > room) {
            if (unit > 1) message += " of at least " + std::to_string(unit) + " bytes";
        } else {
            message += ", " + std::to_string(instances) + " instances in all up to here of at least " +
                       std::to_string(total) + " bytes,";
        }
        message += " but only " + std::to_string(bytes) + " bytes follow the header";
        diagnostics.error(locateOffset(path, in, element.offset), message);
        return false;
    }
    return true;
}

// Assimp converts a list's length to unsigned int unchecked (PLY::PropertyInstance::ConvertTo):
// from a float that is undefined, and can be any size. A length is a whole number.
bool checkListLengths(const std::string& path, std::ifstream& in, const PlyHeader& header, Diagnostics& diagnostics) {
    for (const PlyElement& element : header.elements)
        for (const PlyProperty& property : element.properties) {
            if (!property.list || (property.count_type != PlyType::Float && property.count_type != PlyType::Double))
                continue;
            diagnostics.error(locateOffset(path, in, element.offset),
                              "PLY element " + elementName(element) + " has a list " + printable(property.name) +
                                  " whose length is a floating-point number: a list length must be a whole number");
            return false;
        }
    return true;
}

// The file's bytes at increasing offsets, through a window.
class ByteWindow {
public:
    ByteWindow(std::ifstream& in, uint64_t size) : in_(in), size_(size) {}
    // `count` (at most 8) bytes at `offset`, which lie in the file.
    void read(uint64_t offset, size_t count, unsigned char* out) {
        if (offset < start_ || offset + count > start_ + window_.size()) {
            start_ = offset;
            window_.resize(static_cast<size_t>(std::min<uint64_t>(size_t(1) << 16, size_ - offset)));
            in_.clear();
            in_.seekg(static_cast<std::streamoff>(offset));
            in_.read(reinterpret_cast<char*>(window_.data()), static_cast<std::streamsize>(window_.size()));
        }
        std::memcpy(out, window_.data() + (offset - start_), count);
    }

private:
    std::ifstream& in_;
    uint64_t size_;
    uint64_t start_ = 0;
    std::vector<unsigned char> window_;
};

// A binary list length as Assimp makes it: the value in the file's byte order, then
// converted to unsigned int (a negative signed one wraps).
uint32_t binaryListLength(const unsigned char* raw, PlyType type, bool big_endian) {
    const size_t size = binarySize(type);
    uint32_t value = 0;
    for (size_t i = 0; i < size; ++i) value |= uint32_t{raw[big_endian ? size - 1 - i : i]} << (8 * i);
    switch (type) {
    case PlyType::Char: return static_cast<uint32_t>(static_cast<int32_t>(static_cast<int8_t>(value)));
    case PlyType::Short: return static_cast<uint32_t>(static_cast<int32_t>(static_cast<int16_t>(value)));
    default: return value;
    }
}

// Binary data must lie within the file: past its end Assimp 5.2.5 reads the '\n' bytes its
// buffer starts with (or an earlier block's), as values and as list lengths, and then throws
// "File corrupted", leaking the mesh it was building. Each list's length is read as Assimp
// reads it; its entries must fit.
bool checkBinaryBody(const std::string& path, std::ifstream& in, const PlyHeader& header, uint64_t file_size,
                     Diagnostics& diagnostics) {
    ByteWindow window(in, file_size);
    uint64_t at = header.body;
    const auto refuse = [&](const PlyElement& element, uint64_t instance, const std::string& what) {
        diagnostics.error(locateOffset(path, in, element.offset),
                          "PLY element " + elementName(element) + " runs past the end of the file: its instance " +
                              std::to_string(instance + 1) + " of " + std::to_string(element.count) + " " + what +
                              " (Assimp 5.2.5 would read on into whatever its buffer holds)");
        return false;
    };
    for (const PlyElement& element : header.elements) {
        if (element.kind == ElementKind::TextureFile) continue;
        const bool lists = std::any_of(element.properties.begin(), element.properties.end(),
                                       [](const PlyProperty& p) { return p.list; });
        if (!lists) {  // instances of one size
            uint64_t unit = 0;
            for (const PlyProperty& property : element.properties) unit += binarySize(property.type);
            if (unit * element.count > file_size - at)
                return refuse(element, (file_size - at) / unit, "ends after the file's last byte");
            at += unit * element.count;
            continue;
        }
        for (uint64_t i = 0; i < element.count; ++i)
            for (const PlyProperty& property : element.properties) {
                const size_t size = binarySize(property.list ? property.count_type : property.type);
                if (size > file_size - at) return refuse(element, i, "ends after the file's last byte");
                if (!property.list) {
                    at += size;
                    continue;
                }
                unsigned char raw[8];
                window.read(at, size, raw);
                at += size;
                const uint64_t entries = binaryListLength(raw, property.count_type, header.big_endian);
                if (entries * binarySize(property.type) > file_size - at)
                    return refuse(element, i,
                                  "has a list " + printable(property.name) + " of " + std::to_string(entries) +
                                      " entries, more than the file's last " + std::to_string(file_size - at) +
                                      " bytes hold");
                at += entries * binarySize(property.type);
            }
    }
    return true;
}

// What Assimp's number parsers throw, here (its own exception class is not exported).
struct NotANumber {
    template <class... Parts>
    explicit NotANumber(Parts&&...) {}
};

// Where Assimp's ASCII parse of one value of `type` at `at` ends (PLY::PropertyInstance::
// ParseValue), and the value as a list length (ConvertTo<unsigned int>); false when Assimp
// throws on it (a float that is not a number, or an exponent without digits).
bool asciiValue(const char*& at, PlyType type, uint32_t& length) {
    switch (type) {
    case PlyType::UInt:
    case PlyType::UShort:
    case PlyType::UChar: length = Assimp::strtoul10(at, &at); return true;
    case PlyType::Int:
    case PlyType::Short:
    case PlyType::Char: {
        // strtol10, in unsigned arithmetic (Assimp negates an int, undefined for INT_MIN).
        const bool negative = *at == '-';
        if (negative || *at == '+') ++at;
        const uint32_t magnitude = Assimp::strtoul10(at, &at);
        length = negative ? 0u - magnitude : magnitude;
        return true;
    }
    case PlyType::Float:
    case PlyType::Double:
        try {
            double value = 0.0;
            at = Assimp::fast_atoreal_move<double, NotANumber>(at, value);
            length = 0;
            return true;
        } catch (const NotANumber&) {
            return false;
        }
    case PlyType::Invalid: break;
    }
    return true;
}

// ASCII data as PLY::DOM::ParseElementInstanceLists reads it, one line per instance: an
// element Assimp does not know, or one without properties, is skipped a line at a time; the
// others are parsed value by value, and a parse that runs past a line end goes on in what an
// earlier line left in the buffer. Refused: a value Assimp would throw on after building the
// mesh (which leaks: finding 5's kind), a list longer than the rest of its line (Assimp
// reserves it first: finding 11's kind), and an instance with no line left (Assimp parses
// the last one again).
bool checkAsciiBody(const std::string& path, std::ifstream& in, const PlyHeader& header, AssimpStream& stream,
                    LineBuffer& b, Diagnostics& diagnostics) {
    stream.nextLine(b);
    bool line = stream.delivered();
    for (const PlyElement& element : header.elements) {
        if (element.kind == ElementKind::TextureFile) continue;
        const bool skipped = element.kind == ElementKind::Other || element.properties.empty();
        const std::string which = "PLY element " + elementName(element) + " ";
        for (uint64_t i = 0; i < element.count; ++i) {
            const std::string instance = "instance " + std::to_string(i + 1) + " of " + std::to_string(element.count);
            if (!line) {
                diagnostics.error(locateOffset(path, in, element.offset),
                                  which + "declares " + std::to_string(element.count) + " instances, a line each, but the "
                                          "file ends before " + instance);
                return false;
            }
            if (skipped) {
                skipComments(b);
                skipLine(b);
            } else {
                const char* const start = b.data();
                const char* at = start;
                for (const PlyProperty& property : element.properties) {
                    if (!Assimp::SkipSpaces(&at)) continue;  // Assimp keeps a default value
                    const char* value = at;
                    uint32_t length = 0;
                    bool read = asciiValue(at, property.list ? property.count_type : property.type, length);
                    if (read && property.list) {
                        const char* end = at;
                        while (!Assimp::IsLineEnd(*end)) ++end;
                        if (length > static_cast<uint64_t>(end - at)) {
                            diagnostics.error(locateOffset(path, in, stream.offsetOf(b, value, start)),
                                              which + instance + " has a list " + printable(property.name) + " of " +
                                                  std::to_string(length) + " entries on a line with room for " +
                                                  std::to_string(end - at));
                            return false;
                        }
                        for (uint32_t entry = 0; read && entry < length && Assimp::SkipSpaces(&at); ++entry) {
                            value = at;
                            uint32_t ignored = 0;
                            read = asciiValue(at, property.type, ignored);
                        }
                    }
                    if (!read) {
                        const char* end = value;
                        while (!Assimp::IsSpaceOrNewLine(*end)) ++end;
                        diagnostics.error(locateOffset(path, in, stream.offsetOf(b, value, start)),
                                          which + instance + ": Assimp 5.2.5 cannot read " +
                                              printable(std::string_view(value, static_cast<size_t>(end - value))) +
                                              " as a number for " + printable(property.name) +
                                              " (it would fail and leak the mesh)");
                        return false;
                    }
                    Assimp::SkipSpacesAndLineEnd(&at);
                }
            }
            stream.nextLine(b);
            line = stream.delivered();
        }
    }
    return true;
}

}  // namespace

bool checkPlyInput(const std::string& path, size_t max_bytes, Diagnostics& diagnostics) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) return true;  // the reader reports it
    const std::streamoff end = in.tellg();
    if (end <= 0 || static_cast<uint64_t>(end) > max_bytes) return true;  // empty, or too large: refused elsewhere
    const uint64_t file_size = static_cast<uint64_t>(end);

    // The magic is the first line, after any line ends, as Assimp reads it.
    AssimpStream stream(in, file_size);
    LineBuffer magic;
    stream.nextLine(magic);
    if (stream.overrun() || magic.size() < 3 || std::tolower(static_cast<unsigned char>(magic.data()[0])) != 'p' ||
        std::tolower(static_cast<unsigned char>(magic.data()[1])) != 'l' ||
        std::tolower(static_cast<unsigned char>(magic.data()[2])) != 'y')
        return true;  // not PLY: another importer, or Assimp refuses it cleanly
    const uint64_t magic_at = stream.offsetOf(magic);
    if (!checkHeaderEnds(path, in, magic_at, diagnostics)) return false;

    PlyHeader header;
    LineBuffer buffer;
    switch (readHeader(stream, buffer, header)) {
    case HeaderRead::AssimpRefuses: return true;
    case HeaderRead::NeverEnds:
        diagnostics.error(locateOffset(path, in, magic_at),
                          "PLY header does not end where Assimp 5.2.5 reads it: it would read on past the file");
        return false;
    case HeaderRead::Parsed: break;
    }
    return checkOneOfEach(path, in, header, diagnostics) && checkNoStrips(path, in, header, diagnostics) &&
           checkPropertyPairs(path, in, header, diagnostics) && checkListLengths(path, in, header, diagnostics) &&
           checkCounts(path, in, header, file_size, diagnostics) &&
           (header.binary ? checkBinaryBody(path, in, header, file_size, diagnostics)
                          : checkAsciiBody(path, in, header, stream, buffer, diagnostics));
}

}  // namespace radbake
