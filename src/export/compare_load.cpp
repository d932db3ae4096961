// Loaders for `radbake compare`: glb, PLY, probes.csv and EXR files into plain structs.
#include "export/compare_load.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "core/diagnostics.h"
#include "core/regular_file.h"
#include "export/json_detail.h"

namespace radbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

// A FIFO named on the command line fails the comparison; it never blocks it.
std::string readBytes(const fs::path& path) {
    std::string why;
    std::optional<std::string> bytes = readRegularFile(path.string(), why);
    if (!bytes) fail("cannot open: " + why);
    return std::move(*bytes);
}

template <typename T>
T readLe(const std::string& bytes, size_t offset) {
    if (offset > bytes.size() || sizeof(T) > bytes.size() - offset) fail("truncated");
    T value;
    std::memcpy(&value, bytes.data() + offset, sizeof(T));
    return value;
}

// ---- glb ----

// glTF lookups that fail with the key or index named (nlohmann's own messages do not say
// which key of which object).
const json* find(const json& object, const std::string& key) {
    if (!object.is_object()) return nullptr;
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

const json& at(const json& object, const std::string& key) {
    const json* value = find(object, key);
    if (!value) fail("glTF JSON: missing \"" + key + "\"");
    return *value;
}

const json& at(const json& array, size_t index) {
    if (!array.is_array() || index >= array.size())
        fail("glTF JSON: index " + std::to_string(index) + " out of range");
    return array[index];
}

// A non-negative integer; 5126.0 is accepted as 5126 (JSON does not tell them apart).
size_t indexOf(const json& value) {
    if (value.is_number_unsigned()) return value.get<size_t>();
    if (value.is_number_integer() && value.get<int64_t>() >= 0) return static_cast<size_t>(value.get<int64_t>());
    if (value.is_number_float()) {
        const double number = value.get<double>();
        if (number >= 0.0 && number == std::floor(number) && number < 9007199254740992.0) return static_cast<size_t>(number);
    }
    fail("glTF JSON: expected an index");
}

size_t indexOr(const json& object, const std::string& key, size_t fallback) {
    const json* value = find(object, key);
    return value ? indexOf(*value) : fallback;
}

std::string stringOf(const json& value) {
    if (!value.is_string()) fail("glTF JSON: expected a string");
    return value.get<std::string>();
}

// The BIN chunk of a glb and its JSON, for reading float accessors.
struct GlbFile {
    std::string bytes;
    json root;
    size_t bin_offset = 0, bin_length = 0;

    // A float accessor of `components` per element, e.g. COLOR_0 (3) or TEXCOORD_1 (2).
    std::vector<double> floats(size_t accessor_index, size_t components, const std::string& what) const {
        const json& accessor = at(at(root, "accessors"), accessor_index);
        const char* type = components == 2 ? "VEC2" : components == 3 ? "VEC3" : "SCALAR";
        if (indexOf(at(accessor, "componentType")) != 5126 || stringOf(at(accessor, "type")) != type)
            fail("glb: " + what + " is not float " + type);
        const json& view = at(at(root, "bufferViews"), indexOf(at(accessor, "bufferView")));
        const size_t count = indexOf(at(accessor, "count"));
        const size_t stride = indexOr(view, "byteStride", 4 * components);
        const size_t start = indexOr(view, "byteOffset", 0) + indexOr(accessor, "byteOffset", 0);
        if (count > 0 && (count > bin_length || start + (count - 1) * stride + 4 * components > bin_length))
            fail("glb: " + what + " is outside the buffer");
        std::vector<double> out;
        out.reserve(count * components);
        for (size_t v = 0; v < count; ++v)
            for (size_t c = 0; c < components; ++c)
                out.push_back(readLe<float>(bytes, bin_offset + start + v * stride + 4 * c));
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
    try {
        glb.root = json::parse(std::string_view(bytes).substr(20, json_length));
    } catch (const json::parse_error& e) {
        fail(std::string("glTF JSON: ") + e.what());
    }
    glb.bin_offset = 20 + json_length;
    if (glb.bin_offset + 8 <= bytes.size()) {
        glb.bin_length = readLe<uint32_t>(bytes, glb.bin_offset);
        glb.bin_offset += 8;
        if (glb.bin_offset + glb.bin_length > bytes.size()) fail("glb: truncated BIN chunk");
    }
    return glb;
}

// `attribute` of `attributes` as floats, or nothing when the primitive does not have it.
std::vector<double> optionalFloats(const GlbFile& glb, const json& attributes, const char* attribute, size_t components,
                                   const std::string& group, size_t count) {
    const json* accessor = find(attributes, attribute);
    if (!accessor) return {};
    const std::string what = attribute + (" of " + group);
    std::vector<double> values = glb.floats(indexOf(*accessor), components, what);
    if (values.size() != count * components) fail("glb: " + what + " does not have one value per vertex");
    return values;
}

// ---- PLY ----

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

std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> fields;
    std::string field;
    std::istringstream in(line);
    while (std::getline(in, field, ',')) fields.push_back(field);
    return fields;
}

}  // namespace

// The baked light of every primitive of every mesh, in file order: _RADBAKE_LIGHT (exact), or
// COLOR_0 in files without it (older bakes, which wrote the exact value there).
MeshFile loadGlbFile(const fs::path& path) {
    const GlbFile glb = readGlb(path);
    MeshFile file;
    const json* meshes = find(glb.root, "meshes");
    const size_t mesh_count = meshes && meshes->is_array() ? meshes->size() : 0;
    for (size_t m = 0; m < mesh_count; ++m) {
        const json& mesh = at(*meshes, m);
        const json* name = find(mesh, "name");
        const json& primitives = at(mesh, "primitives");
        const size_t primitive_count = primitives.is_array() ? primitives.size() : 0;
        for (size_t p = 0; p < primitive_count; ++p) {
            const json& primitive = at(primitives, p);
            const json& attributes = at(primitive, "attributes");
            VertexBlock block;
            block.name = "mesh " + (name ? "'" + stringOf(*name) + "'" : std::to_string(m));
            if (primitive_count > 1) block.name += " primitive " + std::to_string(p);
            block.light_attribute = find(attributes, "_RADBAKE_LIGHT") ? "_RADBAKE_LIGHT" : "COLOR_0";
            const json* color = find(attributes, block.light_attribute);
            if (!color) fail("glb: " + block.name + " has no COLOR_0");
            block.light = glb.floats(indexOf(*color), 3, block.light_attribute + " of " + block.name);
            block.count = block.light.size() / 3;
            block.positions = optionalFloats(glb, attributes, "POSITION", 3, block.name, block.count);
            block.normals = optionalFloats(glb, attributes, "NORMAL", 3, block.name, block.count);
            block.uv0 = optionalFloats(glb, attributes, "TEXCOORD_0", 2, block.name, block.count);
            block.uv1 = optionalFloats(glb, attributes, "TEXCOORD_1", 2, block.name, block.count);
            if (const json* extras = find(primitive, "extras"))
                if (const json* lightmap = find(*extras, "radbake_lightmap")) block.lightmap = stringOf(*lightmap);
            file.blocks.push_back(std::move(block));
        }
    }
    return file;
}

MeshFile loadPlyFile(const fs::path& path) {
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
    const size_t body = end + std::strlen("end_header\n");
    if (stride > 0 && vertices > (bytes.size() - body) / stride) fail("ply: truncated vertex data");

    VertexBlock block;
    block.count = vertices;
    block.light_attribute = "red green blue";
    // The properties `names` (all or none of them) into `out`; a colour must be there, and is
    // read as a float, double or uchar / 255.
    const auto read = [&](std::vector<double>& out, std::initializer_list<const char*> names, bool colour) {
        std::vector<std::pair<size_t, std::string>> columns;
        for (const char* name : names) {
            const auto it = properties.find(name);
            if (it == properties.end()) {
                if (columns.empty() && !colour) return;  // absent as a whole
                fail(std::string("ply: no '") + name + "' property");
            }
            columns.push_back(it->second);
        }
        out.reserve(vertices * columns.size());
        for (size_t v = 0; v < vertices; ++v) {
            for (const auto& [offset, type] : columns) {
                const size_t at = body + v * stride + offset;
                if (!colour) out.push_back(plyValue(bytes, at, type));
                else if (type == "float" || type == "float32") out.push_back(readLe<float>(bytes, at));
                else if (type == "double" || type == "float64") out.push_back(readLe<double>(bytes, at));
                else if (type == "uchar" || type == "uint8") out.push_back(readLe<uint8_t>(bytes, at) / 255.0);
                else fail("ply: colour property of type " + type);
            }
        }
    };
    read(block.light, {"red", "green", "blue"}, true);
    read(block.positions, {"x", "y", "z"}, false);
    read(block.normals, {"nx", "ny", "nz"}, false);
    read(block.uv1, {"u1", "v1"}, false);
    block.has_atlas = properties.count("lightmap") > 0;
    read(block.atlas, {"lightmap"}, false);
    MeshFile file;
    file.blocks.push_back(std::move(block));
    return file;
}

// r,g,b per probe; the columns before r (position, normal) are kept as written.
ProbeFile loadProbesFile(const fs::path& path) {
    std::istringstream in(readBytes(path));
    ProbeFile file;
    if (!std::getline(in, file.header)) fail("probes.csv: empty");
    const std::vector<std::string> header = splitCsv(file.header);
    const auto column = [&](const char* name) {
        const auto it = std::find(header.begin(), header.end(), name);
        if (it == header.end()) fail(std::string("probes.csv: no '") + name + "' column");
        return static_cast<size_t>(it - header.begin());
    };
    const size_t r = column("r"), g = column("g"), b = column("b");
    const size_t first_value = std::min({r, g, b});
    std::string line;
    for (int line_number = 2; std::getline(in, line); ++line_number) {
        if (line.empty()) continue;
        const std::vector<std::string> fields = splitCsv(line);
        if (fields.size() != header.size())
            fail("probes.csv: line " + std::to_string(line_number) + " has the wrong number of fields");
        std::string place;
        for (size_t f = 0; f < first_value; ++f) place += fields[f] + (f + 1 < first_value ? "," : "");
        file.places.push_back(std::move(place));
        for (size_t f : {r, g, b}) {
            char* stop = nullptr;
            file.rgb.push_back(std::strtod(fields[f].c_str(), &stop));
            if (stop == fields[f].c_str()) fail("probes.csv: line " + std::to_string(line_number) + ": not a number");
        }
    }
    return file;
}

RgbImage loadExrFile(const fs::path& path) {
    Diagnostics diagnostics;
    std::optional<RgbImage> image = readExr(path, diagnostics);
    if (!image) fail(diagnostics.all().empty() ? "cannot read EXR" : diagnostics.all().back().message);
    return std::move(*image);
}

}  // namespace radbake
