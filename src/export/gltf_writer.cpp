#include "export/gltf_writer.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

#include "export/json_detail.h"
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

using json_detail::GltfJson;

GltfJson vec3Json(const Vec3& v) { return GltfJson::array({v.x, v.y, v.z}); }

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
    GltfJson buffer_views = GltfJson::array(), accessors = GltfJson::array(), meshes = GltfJson::array(),
             nodes = GltfJson::array();
};

// One tightly packed buffer view (offsets stay 4-byte aligned: every element is 4-byte sized).
int addView(JsonLists& lists, size_t offset, size_t length, int target) {
    lists.buffer_views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}, {"target", target}});
    return static_cast<int>(lists.buffer_views.size()) - 1;
}

// `min` and `max` (arrays) are written when given.
int addAccessor(JsonLists& lists, int view, int component_type, size_t count, const char* type,
                const GltfJson& min = nullptr, const GltfJson& max = nullptr) {
    GltfJson accessor = {{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (!min.is_null()) accessor["min"] = min;
    if (!max.is_null()) accessor["max"] = max;
    lists.accessors.push_back(std::move(accessor));
    return static_cast<int>(lists.accessors.size()) - 1;
}

int addVec3Accessor(JsonLists& lists, std::string& bin, const std::vector<Vec3>& data, bool with_bounds) {
    const size_t offset = bin.size();
    append(bin, data);
    const int view = addView(lists, offset, data.size() * sizeof(Vec3), kArrayBuffer);
    if (!with_bounds) return addAccessor(lists, view, kFloat, data.size(), "VEC3");
    Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Vec3& p : data) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    return addAccessor(lists, view, kFloat, data.size(), "VEC3", vec3Json(lo), vec3Json(hi));
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
    return addAccessor(lists, view, kFloat, data.size(), "VEC2", GltfJson::array({lo.x, lo.y}),
                       GltfJson::array({hi.x, hi.y}));
}

// One triangle primitive's accessors and JSON; `uv` (the lightmap UVs) may be null.
struct PrimitiveData {
    const std::vector<Vec3>& positions;
    const std::vector<Vec3>& normals;
    const std::vector<Vec3>& colors;
    const std::vector<Vec2>* uv;
    const std::vector<UVec3>& triangles;
};

// `material` < 0: none; `extras` is written when not null.
GltfJson primitiveJson(JsonLists& lists, std::string& bin, const PrimitiveData& data, int material,
                       const GltfJson& extras = nullptr) {
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
    GltfJson attributes = {{"POSITION", position}, {"NORMAL", normal}, {"COLOR_0", color}, {"_RADBAKE_LIGHT", light}};
    // Both UV sets share one accessor (see the header: radbake has no material UVs).
    if (uv >= 0) {
        attributes["TEXCOORD_0"] = uv;
        attributes["TEXCOORD_1"] = uv;
    }
    GltfJson primitive = {{"attributes", std::move(attributes)}, {"indices", indices}, {"mode", 4}};
    if (material >= 0) primitive["material"] = material;
    if (!extras.is_null()) primitive["extras"] = extras;
    return primitive;
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

GltfJson materialJson(const Material& material, bool& uses_strength) {
    const Vec3 rho = glm::clamp(material.reflectance, Vec3(0.0f), Vec3(1.0f));
    GltfJson json = {{"name", material.name},
                     {"pbrMetallicRoughness",
                      {{"baseColorFactor", {rho.x, rho.y, rho.z, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}};
    const Vec3 emission = isFinite(material.emission) ? glm::max(material.emission, Vec3(0.0f)) : Vec3(0.0f);
    const float peak = std::max({emission.x, emission.y, emission.z});
    if (peak > 1.0f) {
        // emissiveFactor is limited to [0, 1]; the extension carries the scale.
        json["emissiveFactor"] = vec3Json(emission / peak);
        json["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", peak}}}};
        uses_strength = true;
    } else if (peak > 0.0f) {
        json["emissiveFactor"] = vec3Json(emission);
    }
    return json;
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
        const int material = mesh.material < scene.materials.size() ? static_cast<int>(mesh.material) : -1;
        GltfJson primitives = GltfJson::array(), mesh_extras;
        const LightmapMesh* lightmap_mesh = options.lightmaps ? &options.lightmaps->meshes[m] : nullptr;
        if (lightmap_mesh && !lightmap_mesh->triangles.empty()) {
            // One primitive per atlas: an engine binds one lightmap texture per primitive.
            const std::vector<Vec3> normals = lightmapVertexNormals(mesh, *lightmap_mesh);
            const std::vector<Vec3> colors = lightmapVertexValues(mesh, *lightmap_mesh, &bake.values[m], non_finite);
            std::vector<std::string> files;
            for (const int atlas : atlasesUsed(*lightmap_mesh)) {
                const AtlasPart part = atlasPart(*lightmap_mesh, atlas, normals, colors);
                const std::string& file = options.lightmaps->atlas_files[static_cast<size_t>(atlas)];
                const GltfJson extras = {{"radbake_lightmap", file}, {"radbake_lightmap_index", atlas}};
                primitives.push_back(primitiveJson(
                    lists, bin, {part.positions, part.normals, part.colors, &part.uv, part.triangles}, material, extras));
                files.push_back(file);
            }
            mesh_extras = {{"radbake_lightmaps", files}};
        } else {
            primitives.push_back(primitiveJson(
                lists, bin,
                {mesh.positions, vertexNormals(mesh), finiteVertexValues(mesh, &bake.values[m], non_finite), nullptr,
                 mesh.triangles},
                material));
        }
        const std::string name = mesh.name.empty() ? "mesh" + std::to_string(m) : mesh.name;
        GltfJson mesh_json = {{"name", name}, {"primitives", std::move(primitives)}};
        if (!mesh_extras.is_null()) mesh_json["extras"] = std::move(mesh_extras);
        lists.meshes.push_back(std::move(mesh_json));
        lists.nodes.push_back({{"name", name}, {"mesh", lists.meshes.size() - 1}});
    }
    if (non_finite > 0)
        diagnostics.warning({}, std::to_string(non_finite) + " baked vertex values were not finite and were written as 0");

    bool uses_strength = false;
    GltfJson materials = GltfJson::array();
    for (const Material& material : scene.materials) materials.push_back(materialJson(material, uses_strength));

    GltfJson node_indices = GltfJson::array();
    for (size_t i = 0; i < lists.nodes.size(); ++i) node_indices.push_back(i);

    GltfJson asset_extras = {{"_RADBAKE_LIGHT", "baked irradiance H/pi per vertex, linear, unclamped"},
                             {"COLOR_0", "_RADBAKE_LIGHT clamped to [0, 1], as glTF requires"}};
    if (options.lightmaps) {
        asset_extras["TEXCOORD_1"] = "lightmap UVs (TEXCOORD_0 repeats them); u right, v down from the top row";
        asset_extras["radbake_lightmaps"] = options.lightmaps->atlas_files;
    }
    GltfJson root = {{"asset", {{"version", "2.0"}, {"generator", options.generator}, {"extras", std::move(asset_extras)}}}};
    if (uses_strength) root["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    root["scene"] = 0;
    root["scenes"] = GltfJson::array({{{"name", scene.name}, {"nodes", std::move(node_indices)}}});
    root["nodes"] = std::move(lists.nodes);
    root["meshes"] = std::move(lists.meshes);
    if (!materials.empty()) root["materials"] = std::move(materials);
    if (!bin.empty()) {
        root["buffers"] = GltfJson::array({{{"byteLength", bin.size()}}});
        root["bufferViews"] = std::move(lists.buffer_views);
        root["accessors"] = std::move(lists.accessors);
    }
    std::string json = json_detail::dump(root, -1);

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
