// Assimp 5.2.5 tries its glTF 1.0 reader on every .gltf and .glb file (to tell the versions
// apart), and that reader leaks each object it was building when the file turns out to be
// malformed (fuzz_assimp_gltf); its base64 decoder leaks on a byte above 0x7f; its JSON
// parser recurses once per nesting level. Such files are refused here, before Assimp opens
// them: glTF 1.0 was superseded in 2017, base64 is ASCII, and real files nest a few levels.
#include "io/assimp/gltf_guard.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string_view>

namespace radbake {
namespace {

constexpr uint32_t kGlbJsonChunk = 0x4E4F534A;  // "JSON", little endian

// Learns the top-level asset.version and stops there; remembers where a syntax error came.
class VersionFinder final : public nlohmann::json_sax<nlohmann::json> {
public:
    std::optional<std::string> version;
    std::optional<size_t> error_at;

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool string(string_t& text) override {
        if (in_asset_ && depth_ == 2 && version_key_) {
            version = text;
            return false;  // all we need
        }
        return value();
    }
    bool start_object(std::size_t) override {
        ++depth_;
        in_asset_ = in_asset_ || (depth_ == 2 && asset_key_);
        asset_key_ = version_key_ = false;
        return true;
    }
    bool end_object() override {
        if (depth_ == 2) in_asset_ = false;
        --depth_;
        return true;
    }
    bool start_array(std::size_t) override { return start_object(0); }
    bool end_array() override { return end_object(); }
    bool key(string_t& name) override {
        asset_key_ = depth_ == 1 && name == "asset";
        version_key_ = depth_ == 2 && in_asset_ && name == "version";
        return true;
    }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception&) override {
        error_at = position;
        return false;
    }

private:
    bool value() {
        asset_key_ = version_key_ = false;
        return true;
    }
    int depth_ = 0;
    bool asset_key_ = false, version_key_ = false, in_asset_ = false;
};

// What a scan of the JSON text finds first: where nesting exceeds the limit, and where a
// string is a data: URI (as Assimp reads it, escapes decoded) that Assimp misreads: a long
// header (DataUriCheck), or a byte of 0x80 or above after its comma. Assimp 5.2.5's base64 decoder throws on such a byte after
// allocating its output, which then leaks (fuzz_assimp_gltf).
struct JsonScan {
    std::optional<size_t> too_deep_at;
    std::optional<size_t> bad_data_uri_at;
};

// Assimp 5.2.5 notes where a data: URI's parts start in single chars, so a header (what comes
// before the comma) longer than 127 bytes makes it read from before the string
// (fuzz_assimp_gltf); headers of real files are a few dozen bytes.
constexpr size_t kMaxDataUriHeader = 120;

// The decoded prefix, header and payload of one JSON string, fed a decoded character at a time.
class DataUriCheck {
public:
    void start(size_t at) { *this = DataUriCheck(); start_ = at; }
    // False once the string is a data: URI Assimp misreads: a header too long, or a byte of
    // 0x80 or above after the comma.
    bool feed(unsigned code) {
        if (prefix_.size() < 5) {
            prefix_ += static_cast<char>(code < 0x80 ? std::tolower(static_cast<int>(code)) : 0xff);
            header_bytes_ = prefix_.size();
            return true;
        }
        if (prefix_ != "data:") return true;
        if (!after_comma_) {
            after_comma_ = code == ',';
            header_bytes_ += utf8Bytes(code);  // a raw byte of 0x80 or above counts 2: too many is safe
            return header_bytes_ <= kMaxDataUriHeader;
        }
        return code < 0x80;
    }
    size_t start() const { return start_; }

private:
    // Bytes of an escaped code point in UTF-8, at most (a surrogate half counts 3).
    static size_t utf8Bytes(unsigned code) { return code < 0x80 ? 1 : code < 0x800 ? 2 : 3; }

    std::string prefix_;
    bool after_comma_ = false;
    size_t header_bytes_ = 0;
    size_t start_ = 0;
};

// Four hex digits at json[at] (a \u escape's), or 0xffff when they are not there.
unsigned hex4(std::string_view json, size_t at) {
    if (at + 4 > json.size()) return 0xffff;
    unsigned value = 0;
    for (size_t i = at; i < at + 4; ++i) {
        const char c = json[i];
        const int digit = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
        if (digit < 0) return 0xffff;
        value = value * 16 + static_cast<unsigned>(digit);
    }
    return value;
}

JsonScan scanJson(std::string_view json) {
    JsonScan found;
    int depth = 0;
    bool in_string = false;
    DataUriCheck uri;
    for (size_t i = 0; i < json.size() && !found.too_deep_at; ++i) {
        const unsigned char c = static_cast<unsigned char>(json[i]);
        if (!in_string) {
            if (c == '"') {
                in_string = true;
                uri.start(i);
            } else if (c == '[' || c == '{') {
                if (++depth > kMaxGltfNesting) found.too_deep_at = i;
            } else if ((c == ']' || c == '}') && depth > 0) {
                --depth;
            }
            continue;
        }
        unsigned code = c;
        if (c == '"') {
            in_string = false;
            continue;
        }
        if (c == '\\' && i + 1 < json.size()) {
            ++i;
            code = json[i] == 'u' ? hex4(json, i + 1) : static_cast<unsigned char>(json[i]);
            if (json[i] == 'u') i += 4;
        }
        if (!uri.feed(code) && !found.bad_data_uri_at) found.bad_data_uri_at = uri.start();
    }
    return found;
}

// The line and column of json[at] in the file, when the JSON is the whole file; else the
// file alone, with the byte offset in the message.
SourceLocation locate(const std::string& path, std::string_view json, size_t at, bool whole_file) {
    if (!whole_file) return {path, 0, 0};
    at = std::min(at, json.size());
    const size_t line_start = at == 0 ? std::string_view::npos : json.rfind('\n', at - 1);
    const size_t column = line_start == std::string_view::npos ? at + 1 : at - line_start;
    return {path, static_cast<int>(1 + std::count(json.begin(), json.begin() + static_cast<std::ptrdiff_t>(at), '\n')),
            static_cast<int>(column)};
}

bool checkJson(const std::string& path, std::string_view json, size_t base, bool whole_file, Diagnostics& diagnostics) {
    const auto where = [&](size_t at) { return locate(path, json, at, whole_file); };
    const auto byte = [&](size_t at) { return whole_file ? std::string() : " (byte " + std::to_string(base + at) + ")"; };
    const JsonScan scan = scanJson(json);
    if (scan.too_deep_at) {
        diagnostics.error(where(*scan.too_deep_at), "glTF JSON nests arrays and objects more than " +
                                                        std::to_string(kMaxGltfNesting) + " deep" + byte(*scan.too_deep_at) +
                                                        "; not read");
        return false;
    }
    if (scan.bad_data_uri_at) {
        diagnostics.error(where(*scan.bad_data_uri_at),
                          "glTF data: URI that Assimp misreads (a header over " + std::to_string(kMaxDataUriHeader) +
                              " bytes before its comma, or a byte of 0x80 or above after it)" +
                              byte(*scan.bad_data_uri_at) + "; not read");
        return false;
    }
    VersionFinder finder;
    nlohmann::json::sax_parse(json.begin(), json.end(), &finder, nlohmann::json::input_format_t::json, false);
    if (finder.version) {
        if (!finder.version->empty() && (*finder.version)[0] == '2') return true;
        diagnostics.error(where(0), "glTF version '" + finder.version->substr(0, 16) +
                                        "' is not read: only glTF 2.0 is (convert a glTF 1.0 file to 2.0)");
        return false;
    }
    if (finder.error_at) {
        const size_t at = *finder.error_at > 0 ? *finder.error_at - 1 : 0;
        diagnostics.error(where(at), "glTF JSON is malformed" + byte(at) + " before its asset.version; not read");
    } else {
        diagnostics.error(where(0), "JSON file without a top-level asset.version: not a glTF 2.0 file; not read");
    }
    return false;
}

uint32_t readLittle32(const std::string& bytes, size_t at) {
    uint32_t value = 0;
    for (int i = 3; i >= 0; --i) value = (value << 8) | static_cast<unsigned char>(bytes[at + static_cast<size_t>(i)]);
    return value;
}

// A glb: version 1 is glTF 1.0; version 2's first chunk is the JSON Assimp parses.
bool checkGlb(const std::string& path, const std::string& bytes, Diagnostics& diagnostics) {
    if (bytes.size() < 20) return true;  // Assimp refuses a truncated header cleanly
    const uint32_t version = readLittle32(bytes, 4);
    if (version == 1) {
        diagnostics.error({path, 0, 0}, "binary glTF 1.0 is not read: only glTF 2.0 is (convert the file to 2.0)");
        return false;
    }
    if (version != 2 || readLittle32(bytes, 16) != kGlbJsonChunk) return true;
    const size_t length = std::min<size_t>(readLittle32(bytes, 12), bytes.size() - 20);
    return checkJson(path, std::string_view(bytes).substr(20, length), 20, false, diagnostics);
}

// True when the stream starts like glb or JSON: '{' or '[' after any number of blanks (and a
// UTF-8 byte-order mark, which some writers add), as Assimp's JSON parser skips them.
bool looksLikeGltf(std::istream& in) {
    char head[4] = {};
    in.read(head, sizeof head);
    if (in.gcount() == 4 && std::memcmp(head, "glTF", 4) == 0) return true;
    in.clear();
    in.seekg(std::memcmp(head, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0);
    for (int c = in.get(); c != std::char_traits<char>::eof(); c = in.get()) {
        if (c == '{' || c == '[') return true;
        if (c != ' ' && c != '\t' && c != '\r' && c != '\n') return false;
    }
    return false;
}

}  // namespace

bool checkGltfInput(const std::string& path, size_t max_bytes, Diagnostics& diagnostics) {
    std::ifstream in(path, std::ios::binary);
    if (!in || !looksLikeGltf(in)) return true;
    // The whole file, unless it is over the cap (the reader refuses it then).
    in.clear();
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0 || static_cast<uint64_t>(size) > max_bytes) return true;
    std::string bytes(static_cast<size_t>(size), '\0');
    in.seekg(0);
    in.read(bytes.data(), size);
    bytes.resize(static_cast<size_t>(in.gcount()));
    const bool glb = bytes.compare(0, 4, "glTF") == 0;
    return glb ? checkGlb(path, bytes, diagnostics) : checkJson(path, bytes, 0, true, diagnostics);
}

}  // namespace radbake
