// Golden-file comparison. Each kind of file is loaded into Samples (three channels per
// sample plus a layout text that must match), then compared channel by channel.
#include "export/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "core/diagnostics.h"
#include "export/exr_io.h"

namespace radbake {
namespace {

namespace fs = std::filesystem;

struct Samples {
    std::vector<std::string> channel_names;  // three
    std::vector<double> values;              // three per sample
    std::string layout;                      // must be equal on both sides
    const char* unit = "vertex";             // "texel", "vertex", "probe"
    int width = 0;                           // images: texel (x, y) from the index
    std::vector<std::pair<size_t, std::string>> groups;  // (first sample, name), glb meshes
    // Data that must match exactly for the values to be comparable at all: the lightmap UVs
    // (a texel of one bake is not the same surface point in the other otherwise).
    struct Exact {
        std::string name;  // "TEXCOORD_1 of mesh 'floor' primitive 0", "u1 v1", ...
        size_t components = 1;
        std::vector<double> values;
    };
    std::vector<Exact> exact;
    size_t count() const { return values.size() / 3; }
};

// Loading failures are thrown inside this file only and caught in loadSamples.
[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

std::string readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) fail("cannot read");
    return text.str();
}

std::string kindOf(const fs::path& path) {
    const std::string ext = path.extension().string();
    if (ext == ".exr") return "exr";
    if (ext == ".glb") return "glb";
    if (ext == ".ply") return "ply";
    if (path.filename() == "probes.csv") return "probes";
    return "";
}

// ---- a small strict JSON reader, enough for a glb's JSON chunk ----

struct Json {
    enum class Type { Null, Bool, Number, String, Array, Object } type = Type::Null;
    double number = 0.0;
    std::string string;
    std::vector<Json> array;
    std::map<std::string, Json> object;

    const Json* find(const std::string& key) const {
        if (type != Type::Object) return nullptr;
        const auto it = object.find(key);
        return it == object.end() ? nullptr : &it->second;
    }
    const Json& at(const std::string& key) const {
        const Json* value = find(key);
        if (!value) fail("glTF JSON: missing \"" + key + "\"");
        return *value;
    }
    const Json& at(size_t index) const {
        if (type != Type::Array || index >= array.size()) fail("glTF JSON: index " + std::to_string(index) + " out of range");
        return array[index];
    }
    size_t index() const {
        if (type != Type::Number || number < 0 || number != std::floor(number)) fail("glTF JSON: expected an index");
        return static_cast<size_t>(number);
    }
    size_t indexOr(const std::string& key, size_t fallback) const {
        const Json* value = find(key);
        return value ? value->index() : fallback;
    }
};

class JsonReader {
public:
    explicit JsonReader(std::string_view text) : text_(text) {}
    Json document() {
        Json value = parse(0);
        space();
        if (pos_ != text_.size()) error("trailing characters");
        return value;
    }

private:
    [[noreturn]] void error(const char* what) { fail("glTF JSON: " + std::string(what) + " at offset " + std::to_string(pos_)); }
    void space() {
        while (pos_ < text_.size() && std::strchr(" \t\r\n", text_[pos_]) && text_[pos_] != '\0') ++pos_;
    }
    bool eat(char c) {
        space();
        if (pos_ < text_.size() && text_[pos_] == c) return ++pos_, true;
        return false;
    }
    void expect(char c) {
        if (!eat(c)) error("unexpected character");
    }
    Json parse(int depth) {
        if (depth > 64) error("nesting too deep");
        space();
        if (pos_ >= text_.size()) error("unexpected end");
        Json value;
        const char c = text_[pos_];
        if (c == '{') {
            value.type = Json::Type::Object;
            ++pos_;
            if (eat('}')) return value;
            do {
                space();
                std::string key = str();
                expect(':');
                value.object[key] = parse(depth + 1);
            } while (eat(','));
            expect('}');
        } else if (c == '[') {
            value.type = Json::Type::Array;
            ++pos_;
            if (eat(']')) return value;
            do value.array.push_back(parse(depth + 1));
            while (eat(','));
            expect(']');
        } else if (c == '"') {
            value.type = Json::Type::String;
            value.string = str();
        } else if (word("true") || word("false")) {
            value.type = Json::Type::Bool;
        } else if (word("null")) {
        } else {
            const size_t start = pos_;
            while (pos_ < text_.size() && std::strchr("+-0123456789.eE", text_[pos_]) && text_[pos_] != '\0') ++pos_;
            if (start == pos_) error("unexpected character");
            value.type = Json::Type::Number;
            value.number = std::strtod(std::string(text_.substr(start, pos_ - start)).c_str(), nullptr);
        }
        return value;
    }
    bool word(std::string_view w) {
        if (text_.substr(pos_, w.size()) != w) return false;
        pos_ += w.size();
        return true;
    }
    // Escapes other than \uXXXX are decoded; \u keeps the raw text (names are only printed).
    std::string str() {
        if (pos_ >= text_.size() || text_[pos_] != '"') error("expected a string");
        std::string out;
        for (++pos_; pos_ < text_.size() && text_[pos_] != '"'; ++pos_) {
            char c = text_[pos_];
            if (c == '\\' && pos_ + 1 < text_.size()) {
                c = text_[++pos_];
                const char* from = "nrtbf";
                const char* to = "\n\r\t\b\f";
                if (const char* k = std::strchr(from, c); k && c != '\0') c = to[k - from];
                else if (c == 'u') out += "\\";
            }
            out += c;
        }
        if (pos_ >= text_.size()) error("unterminated string");
        ++pos_;
        return out;
    }
    std::string_view text_;
    size_t pos_ = 0;
};

// ---- loaders ----

template <typename T>
T readLe(const std::string& bytes, size_t offset) {
    if (offset + sizeof(T) > bytes.size()) fail("truncated");
    T value;
    std::memcpy(&value, bytes.data() + offset, sizeof(T));
    return value;
}

Samples loadExr(const fs::path& path) {
    Diagnostics diagnostics;
    const std::optional<RgbImage> image = readExr(path, diagnostics);
    if (!image) fail(diagnostics.all().empty() ? "cannot read EXR" : diagnostics.all().back().message);
    Samples samples;
    samples.channel_names = {"R", "G", "B"};
    samples.values.assign(image->rgb.begin(), image->rgb.end());
    samples.layout = std::to_string(image->width) + "x" + std::to_string(image->height) + " image";
    samples.unit = "texel";
    samples.width = image->width;
    return samples;
}

// The BIN chunk of a glb and its JSON, for reading float accessors.
struct GlbFile {
    std::string bytes;
    Json root;
    size_t bin_offset = 0, bin_length = 0;

    // A float accessor of `components` per element, e.g. COLOR_0 (3) or TEXCOORD_1 (2).
    std::vector<double> floats(size_t accessor_index, size_t components, const std::string& what) const {
        const Json& accessor = root.at("accessors").at(accessor_index);
        const char* type = components == 2 ? "VEC2" : components == 3 ? "VEC3" : "SCALAR";
        if (accessor.at("componentType").index() != 5126 || accessor.at("type").string != type)
            fail("glb: " + what + " is not float " + type);
        const Json& view = root.at("bufferViews").at(accessor.at("bufferView").index());
        const size_t count = accessor.at("count").index();
        const size_t stride = view.indexOr("byteStride", 4 * components);
        const size_t start = view.indexOr("byteOffset", 0) + accessor.indexOr("byteOffset", 0);
        if (count > 0 && start + (count - 1) * stride + 4 * components > bin_length)
            fail("glb: " + what + " is outside the buffer");
        std::vector<double> out;
        out.reserve(count * components);
        for (size_t v = 0; v < count; ++v)
            for (size_t c = 0; c < components; ++c) out.push_back(readLe<float>(bytes, bin_offset + start + v * stride + 4 * c));
        return out;
    }
};

GlbFile readGlb(const fs::path& path) {
    GlbFile glb;
    glb.bytes = readBytes(path);
    const std::string& bytes = glb.bytes;
    if (readLe<uint32_t>(bytes, 0) != 0x46546C67u) fail("not a glb file (bad magic)");
    const uint32_t json_length = readLe<uint32_t>(bytes, 12);
    if (readLe<uint32_t>(bytes, 16) != 0x4E4F534Au || 20 + size_t{json_length} > bytes.size()) fail("glb: no JSON chunk");
    glb.root = JsonReader(std::string_view(bytes).substr(20, json_length)).document();
    glb.bin_offset = 20 + json_length;
    if (glb.bin_offset + 8 <= bytes.size()) {
        glb.bin_length = readLe<uint32_t>(bytes, glb.bin_offset);
        glb.bin_offset += 8;
        if (glb.bin_offset + glb.bin_length > bytes.size()) fail("glb: truncated BIN chunk");
    }
    return glb;
}

// The baked light of every primitive of every mesh, in file order: _RADBAKE_LIGHT (exact), or
// COLOR_0 in files without it (older bakes, which wrote the exact value there); a primitive's
// TEXCOORD_1 (lightmap UVs) and lightmap file must match exactly.
Samples loadGlb(const fs::path& path) {
    const GlbFile glb = readGlb(path);
    Samples samples;
    samples.channel_names = {"R", "G", "B"};
    const Json* meshes = glb.root.find("meshes");
    const size_t mesh_count = meshes ? meshes->array.size() : 0;
    for (size_t m = 0; m < mesh_count; ++m) {
        const Json& mesh = meshes->at(m);
        const Json* name = mesh.find("name");
        const Json& primitives = mesh.at("primitives");
        for (size_t p = 0; p < primitives.array.size(); ++p) {
            const Json& primitive = primitives.at(p);
            const Json& attributes = primitive.at("attributes");
            const char* attribute = attributes.find("_RADBAKE_LIGHT") ? "_RADBAKE_LIGHT" : "COLOR_0";
            const Json* color = attributes.find(attribute);
            std::string group = "mesh " + (name ? "'" + name->string + "'" : std::to_string(m));
            if (primitives.array.size() > 1) group += " primitive " + std::to_string(p);
            if (!color) fail("glb: " + group + " has no COLOR_0");
            const std::vector<double> colors = glb.floats(color->index(), 3, attribute + (" of " + group));
            samples.groups.emplace_back(samples.count(), group);
            samples.layout += group + ": " + std::to_string(colors.size() / 3) + " vertices";
            if (const Json* extras = primitive.find("extras"))
                if (const Json* lightmap = extras->find("radbake_lightmap")) samples.layout += ", lightmap " + lightmap->string;
            if (const Json* uv = primitive.at("attributes").find("TEXCOORD_1")) {
                samples.layout += ", TEXCOORD_1";
                const std::string what = "TEXCOORD_1 of " + group;
                samples.exact.push_back({what, 2, glb.floats(uv->index(), 2, what)});
            }
            samples.layout += "\n";
            samples.values.insert(samples.values.end(), colors.begin(), colors.end());
        }
    }
    return samples;
}

size_t plyTypeSize(const std::string& type) {
    if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
    if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
    if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32") return 4;
    if (type == "double" || type == "float64") return 8;
    fail("ply: unknown property type '" + type + "'");
}

double plyValue(const std::string& bytes, size_t at, const std::string& type) {
    if (type == "float" || type == "float32") return readLe<float>(bytes, at);
    if (type == "double" || type == "float64") return readLe<double>(bytes, at);
    if (type == "uchar" || type == "uint8") return readLe<uint8_t>(bytes, at);
    if (type == "char" || type == "int8") return readLe<int8_t>(bytes, at);
    if (type == "ushort" || type == "uint16") return readLe<uint16_t>(bytes, at);
    if (type == "short" || type == "int16") return readLe<int16_t>(bytes, at);
    if (type == "uint" || type == "uint32") return readLe<uint32_t>(bytes, at);
    return readLe<int32_t>(bytes, at);
}

// red/green/blue of the first element (which must be `vertex`) of a binary little-endian PLY;
// the lightmap UVs (u1 v1) and atlas index (lightmap), when present, must match exactly.
Samples loadPly(const fs::path& path) {
    const std::string bytes = readBytes(path);
    const size_t end = bytes.find("end_header\n");
    if (bytes.rfind("ply\n", 0) != 0 || end == std::string::npos) fail("not a PLY file");
    std::istringstream header(bytes.substr(0, end));
    std::string line;
    size_t vertices = 0, stride = 0;
    bool in_vertex = false, seen_element = false;
    std::map<std::string, std::pair<size_t, std::string>> properties;  // name -> (offset, type)
    while (std::getline(header, line)) {
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "format") {
            std::string format;
            words >> format;
            if (format != "binary_little_endian") fail("ply: only binary_little_endian is compared, not " + format);
        } else if (keyword == "element") {
            std::string name;
            words >> name;
            if (!seen_element) {
                if (name != "vertex") fail("ply: the first element is not 'vertex'");
                words >> vertices;
            }
            in_vertex = !seen_element;
            seen_element = true;
        } else if (keyword == "property" && in_vertex) {
            std::string type, name;
            words >> type >> name;
            if (type == "list") fail("ply: list property in vertex element");
            properties[name] = {stride, type};
            stride += plyTypeSize(type);
        }
    }
    Samples samples;
    samples.channel_names = {"red", "green", "blue"};
    samples.layout = std::to_string(vertices) + " vertices";
    const size_t body = end + std::strlen("end_header\n");
    if (body + vertices * stride > bytes.size()) fail("ply: truncated vertex data");
    std::array<std::pair<size_t, std::string>, 3> channels;
    for (int c = 0; c < 3; ++c) {
        const auto it = properties.find(samples.channel_names[c]);
        if (it == properties.end()) fail("ply: no '" + samples.channel_names[c] + "' property");
        channels[c] = it->second;
    }
    for (size_t v = 0; v < vertices; ++v) {
        for (const auto& [offset, type] : channels) {
            const size_t at = body + v * stride + offset;
            if (type == "float" || type == "float32") samples.values.push_back(readLe<float>(bytes, at));
            else if (type == "double" || type == "float64") samples.values.push_back(readLe<double>(bytes, at));
            else if (type == "uchar" || type == "uint8") samples.values.push_back(readLe<uint8_t>(bytes, at) / 255.0);
            else fail("ply: colour property of type " + type);
        }
    }
    const std::vector<std::vector<std::string>> exact_sets = {{"u1", "v1"}, {"lightmap"}};
    for (const std::vector<std::string>& names : exact_sets) {
        if (!properties.count(names.front())) continue;
        Samples::Exact exact;
        for (const std::string& name : names) {
            if (!properties.count(name)) fail("ply: '" + names.front() + "' without '" + name + "'");
            exact.name += (exact.name.empty() ? "" : " ") + name;
        }
        exact.components = names.size();
        for (size_t v = 0; v < vertices; ++v)
            for (const std::string& name : names)
                exact.values.push_back(plyValue(bytes, body + v * stride + properties[name].first, properties[name].second));
        samples.layout += ", " + exact.name;
        samples.exact.push_back(std::move(exact));
    }
    return samples;
}

std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> fields;
    std::string field;
    std::istringstream in(line);
    while (std::getline(in, field, ',')) fields.push_back(field);
    return fields;
}

// r,g,b per probe; the columns before r (position, normal) must match exactly.
Samples loadProbes(const fs::path& path) {
    std::istringstream in(readBytes(path));
    std::string line;
    if (!std::getline(in, line)) fail("probes.csv: empty");
    const std::vector<std::string> header = splitCsv(line);
    const auto column = [&](const char* name) {
        const auto it = std::find(header.begin(), header.end(), name);
        if (it == header.end()) fail(std::string("probes.csv: no '") + name + "' column");
        return static_cast<size_t>(it - header.begin());
    };
    const size_t r = column("r"), g = column("g"), b = column("b");
    const size_t first_value = std::min({r, g, b});
    Samples samples;
    samples.channel_names = {"r", "g", "b"};
    samples.unit = "probe";
    samples.layout = line + "\n";
    for (int line_number = 2; std::getline(in, line); ++line_number) {
        if (line.empty()) continue;
        const std::vector<std::string> fields = splitCsv(line);
        if (fields.size() != header.size()) fail("probes.csv: line " + std::to_string(line_number) + " has the wrong number of fields");
        for (size_t f = 0; f < first_value; ++f) samples.layout += fields[f] + (f + 1 < first_value ? "," : "\n");
        for (size_t f : {r, g, b}) {
            char* stop = nullptr;
            samples.values.push_back(std::strtod(fields[f].c_str(), &stop));
            if (stop == fields[f].c_str()) fail("probes.csv: line " + std::to_string(line_number) + ": not a number");
        }
    }
    return samples;
}

std::optional<Samples> loadSamples(const fs::path& path, const std::string& kind, std::string& problem) {
    try {
        if (kind == "exr") return loadExr(path);
        if (kind == "glb") return loadGlb(path);
        if (kind == "ply") return loadPly(path);
        if (kind == "probes") return loadProbes(path);
        problem = "not a kind radbake compares";
    } catch (const std::exception& e) {
        problem = path.string() + ": " + e.what();
    }
    return std::nullopt;
}

// ---- comparison ----

std::string placeName(const Samples& samples, size_t index) {
    if (samples.width > 0)
        return "texel (" + std::to_string(index % samples.width) + ", " + std::to_string(index / samples.width) + ")";
    for (auto it = samples.groups.rbegin(); it != samples.groups.rend(); ++it)
        if (index >= it->first) return it->second + " vertex " + std::to_string(index - it->first);
    return std::string(samples.unit) + " " + std::to_string(index);
}

// How far beyond tolerance: the smaller of the two ratios; above 1 fails.
double excessOf(double abs_err, double rel_err, const CompareOptions& options) {
    if (abs_err == 0.0) return 0.0;
    const double inf = std::numeric_limits<double>::infinity();
    const double by_abs = options.abs_tol > 0.0 ? abs_err / options.abs_tol : inf;
    const double by_rel = options.rel_tol > 0.0 ? rel_err / options.rel_tol : inf;
    return std::min(by_abs, by_rel);
}

// The first line where two layout texts differ (both lines, without their line breaks).
std::pair<std::string, std::string> firstDifferentLines(const std::string& a, const std::string& b) {
    std::istringstream in_a(a), in_b(b);
    std::string line_a, line_b;
    while (true) {
        const bool got_a = static_cast<bool>(std::getline(in_a, line_a));
        const bool got_b = static_cast<bool>(std::getline(in_b, line_b));
        if (!got_a) line_a = "nothing";
        if (!got_b) line_b = "nothing";
        if (line_a != line_b || (!got_a && !got_b)) return {line_a, line_b};
    }
}

// Empty when the two runs of exact data are equal (NaN matches NaN); else where they differ.
std::string exactDifference(const Samples::Exact& a, const Samples::Exact& b) {
    if (a.name != b.name || a.values.size() != b.values.size()) return "different layouts (" + a.name + " vs " + b.name + ")";
    const auto tuple = [](const Samples::Exact& data, size_t element) {
        std::string text = data.components > 1 ? "(" : "";
        char number[32];
        for (size_t c = 0; c < data.components; ++c) {
            std::snprintf(number, sizeof number, "%.9g", data.values[element * data.components + c]);
            text += (c ? ", " : "") + std::string(number);
        }
        return text + (data.components > 1 ? ")" : "");
    };
    for (size_t i = 0; i < a.values.size(); ++i) {
        const double va = a.values[i], vb = b.values[i];
        if (va == vb || (std::isnan(va) && std::isnan(vb))) continue;
        const size_t element = i / a.components;
        return a.name + " differs at vertex " + std::to_string(element) + ": " + tuple(a, element) + " vs " +
               tuple(b, element) + " (must match exactly)";
    }
    return {};
}

void compareSamples(const Samples& a, const Samples& b, const CompareOptions& options, FileDifference& out) {
    out.samples = a.count();
    if (a.layout != b.layout) {
        out.comparable = false;
        const auto [line_a, line_b] = firstDifferentLines(a.layout, b.layout);
        out.problem = "different layouts (" + line_a + " vs " + line_b + ")";
        return;
    }
    for (size_t e = 0; e < a.exact.size(); ++e) {
        const std::string problem = exactDifference(a.exact[e], b.exact[e]);
        if (!problem.empty()) {
            out.comparable = false;
            out.problem = problem;
            return;
        }
    }
    const double inf = std::numeric_limits<double>::infinity();
    for (size_t c = 0; c < 3; ++c) {
        ChannelDifference channel;
        channel.name = a.channel_names[c];
        double sum_sq = 0.0;
        for (size_t i = 0; i < a.count(); ++i) {
            const double va = a.values[3 * i + c], vb = b.values[3 * i + c];
            double abs_err = std::fabs(va - vb), rel_err = 0.0;
            if (std::isnan(va) && std::isnan(vb)) abs_err = 0.0;
            else if (std::isnan(abs_err)) abs_err = inf;  // NaN on one side, or inf - inf
            if (abs_err > 0.0) rel_err = abs_err / std::max(std::fabs(va), std::fabs(vb));
            if (std::isnan(rel_err)) rel_err = inf;
            sum_sq += abs_err * abs_err;
            channel.max_abs = std::max(channel.max_abs, abs_err);
            channel.max_rel = std::max(channel.max_rel, rel_err);
            const double excess = excessOf(abs_err, rel_err, options);
            if (excess > channel.worst_excess) {
                channel.worst_excess = excess;
                channel.worst = i;
                channel.worst_a = va;
                channel.worst_b = vb;
            }
        }
        channel.rmse = a.count() ? std::sqrt(sum_sq / static_cast<double>(a.count())) : 0.0;
        channel.worst_place = placeName(a, channel.worst);
        if (channel.worst_excess > 1.0) out.within = false;
        out.channels.push_back(channel);
    }
}

FileDifference compareFiles(const fs::path& a, const fs::path& b, const std::string& label, const std::string& kind,
                            const CompareOptions& options) {
    FileDifference out;
    out.file = label;
    out.kind = kind;
    std::string problem;
    const std::optional<Samples> sa = loadSamples(a, kind, problem);
    const std::optional<Samples> sb = sa ? loadSamples(b, kind, problem) : std::nullopt;
    if (!sa || !sb) {
        out.comparable = false;
        out.problem = problem;
        return out;
    }
    compareSamples(*sa, *sb, options, out);
    return out;
}

// Relative paths of every comparable file under `root`, sorted; hidden entries (staging
// directories of a bake in progress) are skipped.
std::vector<std::string> comparableFiles(const fs::path& root) {
    std::vector<std::string> files;
    std::error_code error;
    for (auto it = fs::recursive_directory_iterator(root, error); !error && it != fs::recursive_directory_iterator();
         it.increment(error)) {
        if (it->path().filename().string().rfind('.', 0) == 0) {
            if (it->is_directory()) it.disable_recursion_pending();
            continue;
        }
        if (it->is_regular_file() && !kindOf(it->path()).empty())
            files.push_back(fs::relative(it->path(), root).generic_string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

int CompareResult::exitCode() const {
    if (!problems.empty()) return 2;
    for (const FileDifference& file : files)
        if (!file.comparable) return 2;
    for (const FileDifference& file : files)
        if (!file.within) return 1;
    return 0;
}

CompareResult comparePaths(const fs::path& a, const fs::path& b, const CompareOptions& options) {
    CompareResult result;
    try {
        std::error_code error;
        const bool a_dir = fs::is_directory(a, error), b_dir = fs::is_directory(b, error);
        if (a_dir && b_dir) {
            const std::vector<std::string> in_a = comparableFiles(a), in_b = comparableFiles(b);
            for (const std::string& file : in_b)
                if (!std::binary_search(in_a.begin(), in_a.end(), file)) result.problems.push_back(file + " is only in " + b.string());
            if (in_a.empty()) result.problems.push_back(a.string() + " holds no file radbake compares");
            for (const std::string& file : in_a) {
                if (!std::binary_search(in_b.begin(), in_b.end(), file)) {
                    result.problems.push_back(file + " is missing from " + b.string());
                    continue;
                }
                result.files.push_back(compareFiles(a / file, b / file, file, kindOf(file), options));
            }
        } else if (!a_dir && !b_dir && fs::is_regular_file(a, error) && fs::is_regular_file(b, error)) {
            const std::string kind = kindOf(a);
            if (kind.empty() || kind != kindOf(b))
                result.problems.push_back("cannot compare " + a.string() + " with " + b.string() +
                                          ": not two .exr, .glb, .ply or probes.csv files of the same kind");
            else
                result.files.push_back(compareFiles(a, b, a.filename().string(), kind, options));
        } else {
            for (const fs::path& p : {a, b})
                if (!fs::exists(p, error)) result.problems.push_back(p.string() + " does not exist");
            if (result.problems.empty()) result.problems.push_back("cannot compare a directory with a file");
        }
    } catch (const std::exception& e) {
        result.problems.push_back(std::string("compare failed: ") + e.what());
    }
    return result;
}

std::string formatCompareResult(const CompareResult& result) {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-32s %-6s %10s %12s %12s %12s  %s\n", "file", "chan", "samples", "rmse", "max_abs",
                  "max_rel", "worst");
    out += line;
    for (const FileDifference& file : result.files) {
        if (!file.comparable) {
            out += "NOT COMPARABLE " + file.file + ": " + file.problem + "\n";
            continue;
        }
        for (const ChannelDifference& c : file.channels) {
            std::snprintf(line, sizeof line, "%-32s %-6s %10zu %12.4g %12.4g %12.4g  %s\n", file.file.c_str(), c.name.c_str(),
                          file.samples, c.rmse, c.max_abs, c.max_rel, c.max_abs > 0.0 ? c.worst_place.c_str() : "-");
            out += line;
        }
    }
    for (const std::string& problem : result.problems) out += "NOT COMPARABLE: " + problem + "\n";
    for (const FileDifference& file : result.files) {
        if (!file.comparable || file.within) continue;
        const auto worst = std::max_element(file.channels.begin(), file.channels.end(),
                                            [](const auto& x, const auto& y) { return x.worst_excess < y.worst_excess; });
        std::snprintf(line, sizeof line, "DIFFERS %s: %s %s is %.9g vs %.9g (%.3g times the tolerance)\n", file.file.c_str(),
                      worst->worst_place.c_str(), worst->name.c_str(), worst->worst_a, worst->worst_b, worst->worst_excess);
        out += line;
    }
    const int code = result.exitCode();
    out += code == 0 ? "within tolerance\n" : code == 1 ? "differences beyond tolerance\n" : "not comparable\n";
    return out;
}

}  // namespace radbake
