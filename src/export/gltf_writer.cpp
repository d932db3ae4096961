#include "export/gltf_writer.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>

#include "core/json.h"
#include "export/mesh_attributes.h"
#include "export/output_transaction.h"

namespace radbake {

static_assert(std::endian::native == std::endian::little, "the glb writer copies host floats as little-endian");

namespace {

constexpr uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;     // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;      // "BIN\0"
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;

// %.9g round-trips a float; JSON has no inf/nan, and callers pass only finite values.
std::string num(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", value);
    return buffer;
}

std::string vec3Json(const Vec3& v) { return "[" + num(v.x) + "," + num(v.y) + "," + num(v.z) + "]"; }

template <typename T>
void append(std::string& bin, const std::vector<T>& data) {
    const size_t offset = bin.size();
    bin.resize(offset + data.size() * sizeof(T));
    if (!data.empty()) std::memcpy(bin.data() + offset, data.data(), data.size() * sizeof(T));
}

void appendU32(std::string& out, uint32_t value) {
    char bytes[4];
    std::memcpy(bytes, &value, 4);
    out.append(bytes, 4);
}

struct JsonLists {
    std::vector<std::string> buffer_views, accessors, meshes, nodes;
};

// One tightly packed buffer view (offsets stay 4-byte aligned: every element is 4-byte sized).
int addView(JsonLists& lists, size_t offset, size_t length, int target) {
    lists.buffer_views.push_back("{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
                                 ",\"byteLength\":" + std::to_string(length) +
                                 ",\"target\":" + std::to_string(target) + "}");
    return static_cast<int>(lists.buffer_views.size()) - 1;
}

int addAccessor(JsonLists& lists, int view, int component_type, size_t count, const char* type,
                const std::string& min_max = {}) {
    lists.accessors.push_back("{\"bufferView\":" + std::to_string(view) +
                              ",\"componentType\":" + std::to_string(component_type) +
                              ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"" + min_max + "}");
    return static_cast<int>(lists.accessors.size()) - 1;
}

int addVec3Accessor(JsonLists& lists, std::string& bin, const std::vector<Vec3>& data, bool with_bounds) {
    const size_t offset = bin.size();
    append(bin, data);
    const int view = addView(lists, offset, data.size() * sizeof(Vec3), kArrayBuffer);
    std::string min_max;
    if (with_bounds) {
        Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (const Vec3& p : data) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        min_max = ",\"min\":" + vec3Json(lo) + ",\"max\":" + vec3Json(hi);
    }
    return addAccessor(lists, view, kFloat, data.size(), "VEC3", min_max);
}

// A TEXCOORD accessor, with bounds (optional in glTF, but they let a reader check [0, 1]).
int addVec2Accessor(JsonLists& lists, std::string& bin, const std::vector<Vec2>& data) {
    const size_t offset = bin.size();
    append(bin, data);
    const int view = addView(lists, offset, data.size() * sizeof(Vec2), kArrayBuffer);
    Vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Vec2& p : data) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    return addAccessor(lists, view, kFloat, data.size(), "VEC2",
                       ",\"min\":[" + num(lo.x) + "," + num(lo.y) + "],\"max\":[" + num(hi.x) + "," + num(hi.y) + "]");
}

// One triangle primitive's accessors and JSON; `uv` (the lightmap UVs) may be null.
struct PrimitiveData {
    const std::vector<Vec3>& positions;
    const std::vector<Vec3>& normals;
    const std::vector<Vec3>& colors;
    const std::vector<Vec2>* uv;
    const std::vector<UVec3>& triangles;
};

std::string primitiveJson(JsonLists& lists, std::string& bin, const PrimitiveData& data, const std::string& tail) {
    const int position = addVec3Accessor(lists, bin, data.positions, true);
    const int normal = addVec3Accessor(lists, bin, data.normals, false);
    // glTF requires COLOR_0 in [0, 1]: it gets the clamped value for viewers and engines'
    // vertex colours, and _RADBAKE_LIGHT (an application-specific attribute) the exact one.
    std::vector<Vec3> clamped(data.colors.size());
    for (size_t i = 0; i < clamped.size(); ++i) clamped[i] = glm::clamp(data.colors[i], Vec3(0.0f), Vec3(1.0f));
    const int color = addVec3Accessor(lists, bin, clamped, false);
    const int light = addVec3Accessor(lists, bin, data.colors, false);
    const int uv = data.uv ? addVec2Accessor(lists, bin, *data.uv) : -1;
    const size_t index_offset = bin.size();
    append(bin, data.triangles);  // UVec3 = three packed uint32
    const int index_view = addView(lists, index_offset, data.triangles.size() * sizeof(UVec3), kElementArrayBuffer);
    const int indices = addAccessor(lists, index_view, kUnsignedInt, data.triangles.size() * 3, "SCALAR");
    std::string json = "{\"attributes\":{\"POSITION\":" + std::to_string(position) +
                       ",\"NORMAL\":" + std::to_string(normal) + ",\"COLOR_0\":" + std::to_string(color) +
                       ",\"_RADBAKE_LIGHT\":" + std::to_string(light);
    // Both UV sets share one accessor (see the header: radbake has no material UVs).
    if (uv >= 0) json += ",\"TEXCOORD_0\":" + std::to_string(uv) + ",\"TEXCOORD_1\":" + std::to_string(uv);
    return json + "},\"indices\":" + std::to_string(indices) + ",\"mode\":4" + tail + "}";
}

// The vertices of `lightmap_mesh` on atlas `atlas`, renumbered in order of first use.
struct AtlasPart {
    std::vector<Vec3> positions, normals, colors;
    std::vector<Vec2> uv;
    std::vector<UVec3> triangles;
};

AtlasPart atlasPart(const LightmapMesh& lightmap_mesh, int atlas, const std::vector<Vec3>& normals,
                    const std::vector<Vec3>& colors) {
    AtlasPart part;
    std::vector<uint32_t> renumbered(lightmap_mesh.positions.size(), UINT32_MAX);
    for (const UVec3& t : lightmap_mesh.triangles) {
        if (lightmap_mesh.atlas[t.x] != atlas) continue;  // all three corners share one atlas
        UVec3 out;
        for (int k = 0; k < 3; ++k) {
            uint32_t& index = renumbered[t[k]];
            if (index == UINT32_MAX) {
                index = static_cast<uint32_t>(part.positions.size());
                part.positions.push_back(lightmap_mesh.positions[t[k]]);
                part.normals.push_back(normals[t[k]]);
                part.colors.push_back(colors[t[k]]);
                part.uv.push_back(lightmap_mesh.uv[t[k]]);
            }
            out[k] = index;
        }
        part.triangles.push_back(out);
    }
    return part;
}

// The atlases a lightmap mesh's triangles use, ascending.
std::vector<int> atlasesUsed(const LightmapMesh& lightmap_mesh) {
    std::vector<int> atlases;
    for (const UVec3& t : lightmap_mesh.triangles) atlases.push_back(lightmap_mesh.atlas[t.x]);
    std::sort(atlases.begin(), atlases.end());
    atlases.erase(std::unique(atlases.begin(), atlases.end()), atlases.end());
    return atlases;
}

std::string stringList(const std::vector<std::string>& items) {
    std::string out = "[";
    for (size_t i = 0; i < items.size(); ++i) out += (i ? "," : "") + jsonString(items[i]);
    return out + "]";
}

std::string materialJson(const Material& material, bool& uses_strength) {
    const Vec3 rho = glm::clamp(material.reflectance, Vec3(0.0f), Vec3(1.0f));
    std::string json = "{\"name\":" + jsonString(material.name) +
                       ",\"pbrMetallicRoughness\":{\"baseColorFactor\":[" + num(rho.x) + "," + num(rho.y) + "," +
                       num(rho.z) + ",1],\"metallicFactor\":0,\"roughnessFactor\":1}";
    const Vec3 emission = isFinite(material.emission) ? glm::max(material.emission, Vec3(0.0f)) : Vec3(0.0f);
    const float peak = std::max({emission.x, emission.y, emission.z});
    if (peak > 1.0f) {
        // emissiveFactor is limited to [0, 1]; the extension carries the scale.
        json += ",\"emissiveFactor\":" + vec3Json(emission / peak) +
                ",\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":" + num(peak) + "}}";
        uses_strength = true;
    } else if (peak > 0.0f) {
        json += ",\"emissiveFactor\":" + vec3Json(emission);
    }
    return json + "}";
}

std::string joined(const std::vector<std::string>& items) {
    std::string out = "[";
    for (size_t i = 0; i < items.size(); ++i) out += (i ? "," : "") + items[i];
    return out + "]";
}

}  // namespace

bool checkBakeMatchesScene(const Scene& scene, const VertexBake& bake, Diagnostics& diagnostics) {
    if (bake.values.size() != scene.meshes.size()) {
        diagnostics.error({}, "internal: baked values for " + std::to_string(bake.values.size()) + " meshes, scene has " +
                                  std::to_string(scene.meshes.size()));
        return false;
    }
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (bake.values[m].size() != scene.meshes[m].positions.size()) {
            diagnostics.error(scene.meshes[m].location, "internal: baked values do not match the vertices of mesh '" +
                                                            scene.meshes[m].name + "'");
            return false;
        }
    }
    return true;
}

std::string encodeGlb(const Scene& scene, const VertexBake& bake, const GltfOptions& options,
                      Diagnostics& diagnostics) {
    if (!checkBakeMatchesScene(scene, bake, diagnostics)) return {};
    if (options.lightmaps && !checkLightmapsMatchScene(scene, *options.lightmaps, diagnostics)) return {};

    JsonLists lists;
    std::string bin;
    size_t non_finite = 0;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (mesh.triangles.empty() || mesh.positions.empty()) continue;  // glTF accessors need count >= 1
        const std::string material_tail =
            mesh.material < scene.materials.size() ? ",\"material\":" + std::to_string(mesh.material) : std::string();
        std::string primitives, mesh_extras;
        const LightmapMesh* lightmap_mesh = options.lightmaps ? &options.lightmaps->meshes[m] : nullptr;
        if (lightmap_mesh && !lightmap_mesh->triangles.empty()) {
            // One primitive per atlas: an engine binds one lightmap texture per primitive.
            const std::vector<Vec3> normals = lightmapVertexNormals(mesh, *lightmap_mesh);
            const std::vector<Vec3> colors = lightmapVertexValues(mesh, *lightmap_mesh, &bake.values[m], non_finite);
            std::vector<std::string> files;
            for (const int atlas : atlasesUsed(*lightmap_mesh)) {
                const AtlasPart part = atlasPart(*lightmap_mesh, atlas, normals, colors);
                const std::string& file = options.lightmaps->atlas_files[static_cast<size_t>(atlas)];
                const std::string extras = ",\"extras\":{\"radbake_lightmap\":" + jsonString(file) +
                                           ",\"radbake_lightmap_index\":" + std::to_string(atlas) + "}";
                primitives += std::string(files.empty() ? "" : ",") +
                              primitiveJson(lists, bin, {part.positions, part.normals, part.colors, &part.uv, part.triangles},
                                            material_tail + extras);
                files.push_back(file);
            }
            mesh_extras = ",\"extras\":{\"radbake_lightmaps\":" + stringList(files) + "}";
        } else {
            primitives = primitiveJson(
                lists, bin,
                {mesh.positions, vertexNormals(mesh), finiteVertexValues(mesh, &bake.values[m], non_finite), nullptr,
                 mesh.triangles},
                material_tail);
        }
        const std::string name = mesh.name.empty() ? "mesh" + std::to_string(m) : mesh.name;
        lists.meshes.push_back("{\"name\":" + jsonString(name) + ",\"primitives\":[" + primitives + "]" +
                               mesh_extras + "}");
        lists.nodes.push_back("{\"name\":" + jsonString(name) + ",\"mesh\":" + std::to_string(lists.meshes.size() - 1) + "}");
    }
    if (non_finite > 0)
        diagnostics.warning({}, std::to_string(non_finite) + " baked vertex values were not finite and were written as 0");

    bool uses_strength = false;
    std::vector<std::string> materials;
    for (const Material& material : scene.materials) materials.push_back(materialJson(material, uses_strength));

    std::vector<std::string> node_indices;
    for (size_t i = 0; i < lists.nodes.size(); ++i) node_indices.push_back(std::to_string(i));

    std::string json = "{\"asset\":{\"version\":\"2.0\",\"generator\":" + jsonString(options.generator) +
                       ",\"extras\":{\"_RADBAKE_LIGHT\":\"baked irradiance H/pi per vertex, linear, unclamped\","
                       "\"COLOR_0\":\"_RADBAKE_LIGHT clamped to [0, 1], as glTF requires\"";
    if (options.lightmaps) {
        json += ",\"TEXCOORD_1\":\"lightmap UVs (TEXCOORD_0 repeats them); u right, v down from the top row\"" +
                std::string(",\"radbake_lightmaps\":") + stringList(options.lightmaps->atlas_files);
    }
    json += "}}";
    if (uses_strength) json += ",\"extensionsUsed\":[\"KHR_materials_emissive_strength\"]";
    json += ",\"scene\":0,\"scenes\":[{\"name\":" + jsonString(scene.name) + ",\"nodes\":" + joined(node_indices) + "}]";
    json += ",\"nodes\":" + joined(lists.nodes) + ",\"meshes\":" + joined(lists.meshes);
    if (!materials.empty()) json += ",\"materials\":" + joined(materials);
    if (!bin.empty()) {
        json += ",\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) + "}]";
        json += ",\"bufferViews\":" + joined(lists.buffer_views) + ",\"accessors\":" + joined(lists.accessors);
    }
    json += "}";

    // Chunks are padded to 4 bytes: JSON with spaces, BIN with zeros (glTF 2.0 section 4.4).
    json.resize((json.size() + 3) / 4 * 4, ' ');
    bin.resize((bin.size() + 3) / 4 * 4, '\0');
    const size_t total = 12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size());
    if (total > std::numeric_limits<uint32_t>::max()) {
        diagnostics.error({}, "scene too large for a .glb file (over 4 GiB)");
        return {};
    }
    std::string out;
    out.reserve(total);
    appendU32(out, kGlbMagic);
    appendU32(out, 2);
    appendU32(out, static_cast<uint32_t>(total));
    appendU32(out, static_cast<uint32_t>(json.size()));
    appendU32(out, kChunkJson);
    out += json;
    if (!bin.empty()) {
        appendU32(out, static_cast<uint32_t>(bin.size()));
        appendU32(out, kChunkBin);
        out += bin;
    }
    return out;
}

bool writeGlb(const std::filesystem::path& path, const Scene& scene, const VertexBake& bake,
              const GltfOptions& options, Diagnostics& diagnostics) {
    const std::string bytes = encodeGlb(scene, bake, options, diagnostics);
    if (bytes.empty()) return false;
    return writeFileBytes(path, bytes, diagnostics);
}

}  // namespace radbake
