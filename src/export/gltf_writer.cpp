#include "export/gltf_writer.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <map>
#include <set>

#include "bake/lightmap_charts.h"
#include "core/read_policy.h"
#include "core/regular_file.h"
#include "export/json_detail.h"
#include "export/mesh_attributes.h"
#include "export/output_transaction.h"
#include "export/preview.h"
#include "scene/texture_image.h"

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

// glTF's UVs run v down from the image's top row; the scene's (OBJ's, VRML's) run v up.
Vec2 gltfUv(const Vec2& uv) { return Vec2(uv.x, 1.0f - uv.y); }

std::vector<Vec2> gltfUvs(const std::vector<Vec2>& uv) {
    std::vector<Vec2> out(uv.size());
    std::transform(uv.begin(), uv.end(), out.begin(), gltfUv);
    return out;
}

// Per-vertex tangents (xyz unit, w = +-1 the bitangent's sign) from the UVs, as glTF defines
// them for a normal map: without them a loader makes its own, which need not match (the
// validator warns). Per triangle dP/du summed per vertex (Lengyel), made orthogonal to the
// normal; a vertex whose UVs give no direction gets any unit vector orthogonal to it.
std::vector<Vec4> tangents(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                           const std::vector<Vec2>& uv, const std::vector<UVec3>& triangles) {
    std::vector<DVec3> along_u(positions.size(), DVec3(0.0)), along_v(positions.size(), DVec3(0.0));
    for (const UVec3& t : triangles) {
        const DVec3 e1 = DVec3(positions[t.y]) - DVec3(positions[t.x]), e2 = DVec3(positions[t.z]) - DVec3(positions[t.x]);
        const DVec2 d1 = DVec2(uv[t.y]) - DVec2(uv[t.x]), d2 = DVec2(uv[t.z]) - DVec2(uv[t.x]);
        const double det = d1.x * d2.y - d2.x * d1.y;
        if (!(std::abs(det) > 0.0)) continue;
        const DVec3 u = (e1 * d2.y - e2 * d1.y) / det, v = (e2 * d1.x - e1 * d2.x) / det;
        for (int k = 0; k < 3; ++k) {
            along_u[t[k]] += u;
            along_v[t[k]] += v;
        }
    }
    std::vector<Vec4> out(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        const DVec3 n(normals[i]);
        DVec3 t = along_u[i] - n * glm::dot(n, along_u[i]);
        if (!(glm::length(t) > 1e-12)) t = glm::cross(n, std::abs(n.x) < 0.9 ? DVec3(1, 0, 0) : DVec3(0, 1, 0));
        t = glm::normalize(t);
        const double w = glm::dot(glm::cross(n, t), along_v[i]) < 0.0 ? -1.0 : 1.0;
        out[i] = Vec4(Vec3(t), static_cast<float>(w));
    }
    return out;
}

// One triangle primitive's accessors and JSON; `uv` (the lightmap UVs) and `source_uv` (the
// mesh's own, in glTF's convention) may be null; `with_tangents` (a normal-mapped material)
// adds TANGENT from `source_uv`.
struct PrimitiveData {
    const std::vector<Vec3>& positions;
    const std::vector<Vec3>& normals;
    const std::vector<Vec3>& colors;
    const std::vector<Vec2>* uv;
    const std::vector<UVec3>& triangles;
    const std::vector<Vec2>* source_uv = nullptr;
    bool with_tangents = false;
    // COLOR_0 is left out where the material's lightmap lights the primitive: glTF multiplies
    // the base colour by COLOR_0, so an engine would apply the baked light twice.
    bool with_colors = true;
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
    const int color = data.with_colors ? addVec3Accessor(lists, bin, clamped, false) : -1;
    const int light = addVec3Accessor(lists, bin, data.colors, false);
    const int uv = data.uv ? addVec2Accessor(lists, bin, *data.uv) : -1;
    const int source_uv = data.source_uv ? addVec2Accessor(lists, bin, *data.source_uv) : -1;
    int tangent = -1;
    if (data.source_uv && data.with_tangents) {
        const std::vector<Vec4> values = tangents(data.positions, data.normals, *data.source_uv, data.triangles);
        const size_t offset = bin.size();
        append(bin, values);
        tangent = addAccessor(lists, addView(lists, offset, values.size() * sizeof(Vec4), kArrayBuffer), kFloat,
                              values.size(), "VEC4");
    }
    const size_t index_offset = bin.size();
    append(bin, data.triangles);  // UVec3 = three packed uint32
    const int index_view = addView(lists, index_offset, data.triangles.size() * sizeof(UVec3), kElementArrayBuffer);
    const int indices = addAccessor(lists, index_view, kUnsignedInt, data.triangles.size() * 3, "SCALAR");
    GltfJson attributes = {{"POSITION", position}, {"NORMAL", normal}};
    if (color >= 0) attributes["COLOR_0"] = color;
    attributes["_RADBAKE_LIGHT"] = light;
    // The source UVs are set 0 (what the materials' textures use), the lightmap's set 1.
    // Without source UVs both sets share the lightmap accessor: glTF numbers sets from 0.
    if (tangent >= 0) attributes["TANGENT"] = tangent;
    if (source_uv >= 0) {
        attributes["TEXCOORD_0"] = source_uv;
        if (uv >= 0) attributes["TEXCOORD_1"] = uv;
    } else if (uv >= 0) {
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
    std::vector<Vec2> uv, source_uv;
    std::vector<UVec3> triangles;
};

// `source_uv`: per lightmap vertex, or empty.
AtlasPart atlasPart(const LightmapMesh& lightmap_mesh, int atlas, const std::vector<Vec3>& normals,
                    const std::vector<Vec3>& colors, const std::vector<Vec2>& source_uv) {
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
                if (!source_uv.empty()) part.source_uv.push_back(source_uv[t[k]]);
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

// The textures in the glb: one image per material texture file (PNG and JPEG embedded as
// they are, any other format re-encoded to PNG) and per lightmap atlas, one texture each.
// Two samplers, made on first use: material textures repeat, linear and mipmapped (as the
// bake averaged them); lightmaps clamp to the edge and are not mipmapped (a mip level would
// blend neighbouring charts across their padding).
struct TextureTable {
    std::map<std::string, int> index;  // path -> texture index; -1 when the file cannot be read
    std::vector<int> lightmap_index;   // atlas -> texture index; -1 until used
    GltfJson images = GltfJson::array(), textures = GltfJson::array(), samplers = GltfJson::array();
    int repeat_sampler = -1, lightmap_sampler = -1;
    // The import's read policy, when the scene came from one: a texture read again here must
    // still be a file it allows (a path swapped for a link out of the tree since is refused).
    std::optional<ReadPolicy> policy;
};

int samplerIndex(TextureTable& table, bool lightmap) {
    int& index = lightmap ? table.lightmap_sampler : table.repeat_sampler;
    if (index >= 0) return index;
    if (lightmap) {
        table.samplers.push_back({{"magFilter", 9729}, {"minFilter", 9729}, {"wrapS", 33071}, {"wrapT", 33071}});
    } else {
        table.samplers.push_back({{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}});
    }
    return index = static_cast<int>(table.samplers.size()) - 1;
}

// An image of `bytes` in the BIN chunk and its texture; returns the texture index.
int addImageTexture(TextureTable& table, JsonLists& lists, std::string& bin, const std::string& bytes,
                    const std::string& mime, bool lightmap, const std::string& name = {}) {
    const size_t offset = bin.size();
    bin += bytes;
    bin.resize((bin.size() + 3) / 4 * 4, '\0');  // the next accessor stays 4-byte aligned
    lists.buffer_views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes.size()}});
    GltfJson image = {{"bufferView", lists.buffer_views.size() - 1}, {"mimeType", mime}};
    if (!name.empty()) image["name"] = name;
    table.images.push_back(std::move(image));
    table.textures.push_back({{"sampler", samplerIndex(table, lightmap)}, {"source", table.images.size() - 1}});
    return static_cast<int>(table.textures.size()) - 1;
}

// Empty when it is not a regular file (a FIFO would block the write), is larger than the
// import's cap, cannot be read, or is not a file the policy allows.
std::string fileBytes(const std::string& path, const ReadPolicy* policy) {
    std::string why;
    return readRegularFile(path, why, kDefaultMaxInputBytes, openedCheckOf(policy)).value_or(std::string());
}

// The texture index of `path`, adding its image on first use; -1 when it cannot be read (the
// import warned already).
int textureIndex(TextureTable& table, JsonLists& lists, std::string& bin, const TextureRef& texture) {
    const std::string& path = texture.path;
    if (path.empty()) return -1;
    if (const auto it = table.index.find(path); it != table.index.end()) return it->second;
    const ReadPolicy* policy = table.policy ? &*table.policy : nullptr;
    std::string bytes = texture.embedded ? *texture.embedded : fileBytes(path, policy);
    std::string mime;
    if (bytes.size() >= 8 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0) {
        mime = "image/png";
    } else if (bytes.size() >= 3 && bytes.compare(0, 3, "\xff\xd8\xff") == 0) {
        mime = "image/jpeg";
    } else {
        int width = 0, height = 0;
        std::vector<uint8_t> rgba;
        std::string error;
        bytes = readImageRgba8(texture, width, height, rgba, error, policy) ? encodeRgba8Png(width, height, rgba)
                                                                             : std::string();
        mime = "image/png";
    }
    if (bytes.empty()) return table.index[path] = -1;
    return table.index[path] = addImageTexture(table, lists, bin, bytes, mime, false);
}

// `textured`: every mesh using the material has source UVs, so its textures (TEXCOORD_0) apply.
GltfJson materialJson(const Material& material, bool textured, TextureTable& textures, JsonLists& lists,
                      std::string& bin, bool& uses_strength) {
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
    if (!textured) return json;
    if (const int base = textureIndex(textures, lists, bin, material.base_color_texture); base >= 0) {
        json["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", base}};
        // glTF multiplies texture and factor; a VRML97 RGB texture replaces the colour.
        if (material.base_color_texture.rgb_replaces &&
            imageChannels(material.base_color_texture, textures.policy ? &*textures.policy : nullptr) >= 3)
            json["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 1};
    }
    if (const int emissive = textureIndex(textures, lists, bin, material.emissive_texture); emissive >= 0)
        json["emissiveTexture"] = {{"index", emissive}};
    if (const int normal = textureIndex(textures, lists, bin, material.normal_texture); normal >= 0)
        json["normalTexture"] = {{"index", normal}};
    return json;
}

// The rotation that turns glTF's light direction (-Z of its node) onto `direction` (unit).
Quat rotationFromMinusZ(const Vec3& direction) {
    const DVec3 from(0.0, 0.0, -1.0), to = glm::normalize(DVec3(direction));
    const double c = glm::dot(from, to);
    if (!(c > -1.0 + 1e-9)) return Quat(0.0f, 1.0f, 0.0f, 0.0f);  // opposite: half a turn about X
    const DVec3 axis = glm::cross(from, to);
    return Quat(glm::normalize(glm::dquat(1.0 + c, axis.x, axis.y, axis.z)));
}

// KHR_lights_punctual lights, each on a node of its own (added to `lists`), for lights that
// are on. Units as radbake baked them (punctual_lights.h), not photometric: the glTF
// intensity of a point or spot light is its radiant intensity in W/sr, of a directional
// light its irradiance in W/m^2, with the colour normalised to a largest channel of 1.
// Every light is marked as baked: its light is in the lightmaps and vertex light already.
GltfJson lightsJson(const Scene& scene, JsonLists& lists, Diagnostics& diagnostics) {
    GltfJson lights = GltfJson::array();
    size_t off = 0;
    const Light* first_off = nullptr;
    for (size_t k = 0; k < scene.lights.size(); ++k) {
        const Light& light = scene.lights[k];
        if (!light.on) {
            if (!first_off) first_off = &light;
            ++off;
            continue;
        }
        const Vec3 strength = glm::max(light.color * std::max(light.intensity, 0.0f), Vec3(0.0f));
        const float peak = isFinite(strength) ? std::max({strength.x, strength.y, strength.z}) : 0.0f;
        const char* type = light.type == LightType::Point ? "point" : light.type == LightType::Spot ? "spot" : "directional";
        const std::string name = std::string(light.type == LightType::Point  ? "PointLight "
                                             : light.type == LightType::Spot ? "SpotLight "
                                                                             : "DirectionalLight ") +
                                 std::to_string(k);
        GltfJson extras = {{"radbake_baked", true},
                           {"radbake_note", "already in the baked light: enable it only for what the bake does not "
                                            "hold (dynamic objects, specular)"},
                           {"radbake_units", light.type == LightType::Directional ? "W/m^2" : "W/sr"}};
        GltfJson json = {{"name", name},
                         {"type", type},
                         {"color", vec3Json(peak > 0.0f ? strength / peak : Vec3(1.0f))},
                         {"intensity", peak}};
        if (light.type != LightType::Directional) {
            if (std::isfinite(light.radius) && light.radius > 0.0f) json["range"] = light.radius;
            if (light.attenuation != Vec3(1.0f, 0.0f, 0.0f)) extras["radbake_attenuation"] = vec3Json(light.attenuation);
        }
        if (light.type == LightType::Spot) {
            // glTF wants 0 <= inner < outer <= pi/2, and fades smoothly between them (VRML linearly).
            const float outer = std::clamp(light.cut_off_angle, 1e-4f, static_cast<float>(kPi / 2.0));
            const float inner = std::clamp(light.beam_width, 0.0f, outer * 0.999f);
            json["spot"] = {{"innerConeAngle", inner}, {"outerConeAngle", outer}};
        }
        json["extras"] = std::move(extras);
        GltfJson node = {{"name", name}};
        if (light.type != LightType::Directional)
            node["translation"] = vec3Json(light.position);
        if (light.type != LightType::Point) {
            const Quat q = rotationFromMinusZ(light.direction);
            node["rotation"] = {q.x, q.y, q.z, q.w};
        }
        node["extensions"] = {{"KHR_lights_punctual", {{"light", lights.size()}}}};
        lists.nodes.push_back(std::move(node));
        lights.push_back(std::move(json));
    }
    if (off > 0)
        diagnostics.warning(first_off->location, std::to_string(off) + " light" + (off == 1 ? " is" : "s are") +
                                                     " off: not exported (the bake has none of their light)");
    return lights;
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

    const std::vector<LightmapPng>* lightmap_pngs = options.lightmaps ? options.lightmap_textures : nullptr;
    if (lightmap_pngs && lightmap_pngs->size() != options.lightmaps->atlas_files.size()) {
        diagnostics.error({}, "internal: lightmap textures for " + std::to_string(lightmap_pngs->size()) + " atlases, " +
                                  std::to_string(options.lightmaps->atlas_files.size()) + " atlas files");
        return {};
    }

    JsonLists lists;
    std::string bin;
    size_t non_finite = 0;
    // A material's textures are written only when every mesh using it has UVs for them.
    std::vector<bool> textured(scene.materials.size(), true);
    for (const Mesh& mesh : scene.meshes)
        if (mesh.material < textured.size() && mesh.uv0.size() != mesh.positions.size()) textured[mesh.material] = false;
    auto normalMapped = [&](uint32_t material) {
        return material < textured.size() && textured[material] && !scene.materials[material].normal_texture.empty();
    };

    // One glTF material per (scene material, atlas), made on first use: primitives on two
    // atlases must not share a material, or an importer (Blender) merges them and loses which
    // lightmap each uses. Atlas -1: a primitive without a lightmap. A material keeps its
    // source name unless it spans several atlases (then " (lightmap k)" tells them apart).
    std::vector<std::set<int>> material_atlases(scene.materials.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (mesh.material >= scene.materials.size() || mesh.triangles.empty() || mesh.positions.empty()) continue;
        const LightmapMesh* lightmap_mesh = options.lightmaps ? &options.lightmaps->meshes[m] : nullptr;
        if (lightmap_mesh && !lightmap_mesh->triangles.empty()) {
            for (const int atlas : atlasesUsed(*lightmap_mesh)) material_atlases[mesh.material].insert(atlas);
        } else {
            material_atlases[mesh.material].insert(-1);
        }
    }
    bool uses_strength = false, uses_lightmap = false;
    TextureTable textures;
    if (scene.read_roots) textures.policy = readPolicyFor(scene.source_path, *scene.read_roots);
    textures.lightmap_index.assign(options.lightmaps ? options.lightmaps->atlas_files.size() : 0, -1);
    GltfJson materials = GltfJson::array();
    std::map<std::pair<uint32_t, int>, int> material_index;
    const auto materialFor = [&](uint32_t material, int atlas) -> int {
        if (material >= scene.materials.size()) return -1;
        if (const auto it = material_index.find({material, atlas}); it != material_index.end()) return it->second;
        GltfJson json = materialJson(scene.materials[material], textured[material], textures, lists, bin, uses_strength);
        if (atlas >= 0) {
            const size_t k = static_cast<size_t>(atlas);
            if (material_atlases[material].size() > 1)
                json["name"] = scene.materials[material].name + " (lightmap " + std::to_string(atlas) + ")";
            GltfJson extras = {{"radbake_lightmap", options.lightmaps->atlas_files[k]}, {"radbake_lightmap_index", atlas}};
            if (lightmap_pngs) {
                const LightmapPng& png = (*lightmap_pngs)[k];
                int& texture = textures.lightmap_index[k];
                if (texture < 0)
                    texture = addImageTexture(textures, lists, bin, png.bytes, "image/png", true,
                                              "lightmap " + std::to_string(atlas));
                // three.js (which reads MOZ_lightmap) takes a light map as irradiance and
                // shades it with albedo / pi: the decoded texels hold H/pi, so intensity pi
                // makes them H and albedo * H/pi is what it shows.
                json["extensions"]["MOZ_lightmap"] = {
                    {"index", texture}, {"texCoord", 1}, {"intensity", static_cast<float>(kPi)}};
                extras["radbake_lightmap_png"] = png.file;
                extras["radbake_lightmap_encoding"] = "rgbe8";
                extras["radbake_lightmap_quantity"] = toString(options.lightmaps->quantity);
                if (k < options.lightmaps->shadowmask_files.size())
                    extras["radbake_shadowmask"] = options.lightmaps->shadowmask_files[k];
                if (k < options.lightmaps->direction_files.size())
                    extras["radbake_lightmap_direction"] = options.lightmaps->direction_files[k];
                uses_lightmap = true;
            }
            json["extras"] = std::move(extras);
        }
        materials.push_back(std::move(json));
        return material_index[{material, atlas}] = static_cast<int>(materials.size()) - 1;
    };

    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (mesh.triangles.empty() || mesh.positions.empty()) continue;  // glTF accessors need count >= 1
        GltfJson primitives = GltfJson::array(), mesh_extras;
        const LightmapMesh* lightmap_mesh = options.lightmaps ? &options.lightmaps->meshes[m] : nullptr;
        const bool has_uv = !mesh.uv0.empty() && mesh.uv0.size() == mesh.positions.size();
        if (lightmap_mesh && !lightmap_mesh->triangles.empty()) {
            // One primitive per atlas: an engine binds one lightmap texture per primitive.
            const std::vector<Vec3> normals = lightmapVertexNormals(mesh, *lightmap_mesh);
            const std::vector<Vec3> colors = lightmapVertexValues(mesh, *lightmap_mesh, &bake.values[m], non_finite);
            std::vector<Vec2> source_uv;
            if (has_uv)
                for (size_t v = 0; v < lightmap_mesh->positions.size(); ++v)
                    source_uv.push_back(gltfUv(interpolateSource(*lightmap_mesh, v, std::span<const Vec2>(mesh.uv0))));
            std::vector<std::string> files;
            for (const int atlas : atlasesUsed(*lightmap_mesh)) {
                const AtlasPart part = atlasPart(*lightmap_mesh, atlas, normals, colors, source_uv);
                const std::string& file = options.lightmaps->atlas_files[static_cast<size_t>(atlas)];
                const GltfJson extras = {{"radbake_lightmap", file}, {"radbake_lightmap_index", atlas}};
                const int material = materialFor(mesh.material, atlas);
                primitives.push_back(primitiveJson(lists, bin,
                                                   {part.positions, part.normals, part.colors, &part.uv, part.triangles,
                                                    has_uv ? &part.source_uv : nullptr, normalMapped(mesh.material),
                                                    !(lightmap_pngs && material >= 0)},
                                                   material, extras));
                files.push_back(file);
            }
            mesh_extras = {{"radbake_lightmaps", files}};
        } else {
            const std::vector<Vec2> source_uv = has_uv ? gltfUvs(mesh.uv0) : std::vector<Vec2>();
            primitives.push_back(primitiveJson(
                lists, bin,
                {mesh.positions, vertexNormals(mesh), finiteVertexValues(mesh, &bake.values[m], non_finite), nullptr,
                 mesh.triangles, has_uv ? &source_uv : nullptr, normalMapped(mesh.material)},
                materialFor(mesh.material, -1)));
        }
        const std::string name = mesh.name.empty() ? "mesh" + std::to_string(m) : mesh.name;
        // A back twin (scene/two_sided.h) is the flipped copy that carries the back's light;
        // both sides are single-sided primitives (glTF's default doubleSided false).
        if (mesh.back && mesh.twin < scene.meshes.size()) mesh_extras["radbake_back_of"] = scene.meshes[mesh.twin].name;
        GltfJson mesh_json = {{"name", name}, {"primitives", std::move(primitives)}};
        if (!mesh_extras.is_null()) mesh_json["extras"] = std::move(mesh_extras);
        lists.meshes.push_back(std::move(mesh_json));
        lists.nodes.push_back({{"name", name}, {"mesh", lists.meshes.size() - 1}});
    }
    if (non_finite > 0)
        diagnostics.warning({}, std::to_string(non_finite) + " baked vertex values were not finite and were written as 0");

    // Viewpoints become cameras, so the baked scene opens framed: glTF's camera looks down -Z
    // with +Y up, as VRML's does; yfov is VRML's fieldOfView (the smaller angle: the vertical
    // one of a landscape view). The near plane scales with the scene (1e-4 of its diagonal).
    GltfJson cameras = GltfJson::array();
    const double znear = 1e-4 * lightmapExtent(scene);
    for (size_t k = 0; k < scene.cameras.size(); ++k) {
        const Camera& camera = scene.cameras[k];
        const Quat q = glm::normalize(camera.orientation);
        const float yfov = std::clamp(camera.field_of_view, 1e-3f, 3.1f);
        const std::string name = camera.name.empty() ? "Viewpoint " + std::to_string(k) : camera.name;
        cameras.push_back({{"name", name},
                           {"type", "perspective"},
                           {"perspective", {{"yfov", yfov}, {"znear", static_cast<float>(znear)}}}});
        lists.nodes.push_back({{"name", name},
                               {"camera", k},
                               {"translation", {camera.position.x, camera.position.y, camera.position.z}},
                               {"rotation", {q.x, q.y, q.z, q.w}}});
    }

    GltfJson lights = GltfJson::array();
    if (options.export_lights) lights = lightsJson(scene, lists, diagnostics);

    GltfJson node_indices = GltfJson::array();
    for (size_t i = 0; i < lists.nodes.size(); ++i) node_indices.push_back(i);

    GltfJson asset_extras = {{"_RADBAKE_LIGHT", "baked irradiance H/pi per vertex, linear, unclamped"},
                             {"COLOR_0", "_RADBAKE_LIGHT clamped to [0, 1], as glTF requires"}};
    if (options.lightmaps) {
        asset_extras["TEXCOORD_1"] =
            "lightmap UVs (TEXCOORD_0 repeats them when the mesh has no UVs of its own); u right, v down from the top row";
        asset_extras["radbake_lightmaps"] = options.lightmaps->atlas_files;
        if (!options.lightmaps->direction_files.empty())
            asset_extras["radbake_lightmap_direction"] =
                "directional lightmaps: each material's extras.radbake_lightmap_direction names an EXR holding g (world "
                "x y z) per texel; the irradiance at a normal-mapped normal n is the lightmap's times max(0, 1 + g . (n - "
                "n0)), n0 the surface normal";
        if (!options.lightmaps->shadowmask_files.empty()) {
            asset_extras["radbake_shadowmasks"] = options.lightmaps->shadowmask_files;
            GltfJson channels = GltfJson::object();
            for (const auto& [name, channel] : options.lightmaps->shadowmask_channels) channels[name] = channel;
            asset_extras["radbake_shadowmask_channels"] = std::move(channels);
            asset_extras["radbake_shadowmask"] =
                "mixed lighting: the lights named in radbake_shadowmask_channels are drawn by the engine (their direct "
                "light is in no lightmap texel or vertex); each atlas's shadowmask PNG holds, in that light's channel "
                "(0 R, 1 G, 2 B, 3 A), its visible share per texel, linear, 255 = unshadowed";
        }
        asset_extras["radbake_lightmap_quantity"] =
            options.lightmaps->quantity == LightmapQuantity::Radiance
                ? "radiance: reflectance x H/pi per texel, shown as it is (the base colour is in it)"
                : "irradiance: H/pi per texel, multiplied by the base colour";
        if (lightmap_pngs) {
            GltfJson pngs = GltfJson::array();
            for (const LightmapPng& png : *lightmap_pngs) pngs.push_back(png.file);
            asset_extras["radbake_lightmap_pngs"] = std::move(pngs);
            asset_extras["radbake_lightmap_encoding"] =
                "each atlas also as an 8-bit RGBA PNG with a shared exponent (rgbe8), embedded and referenced from its "
                "materials by MOZ_lightmap through TEXCOORD_1: value = 0 for alpha 0, else channel * 2^(alpha - 136); "
                "decode to linear before sampling (examples/web); MOZ_lightmap.intensity = pi (three.js reads a "
                "light map as irradiance H); primitives with a "
                "lightmap texture have no COLOR_0 (an engine would apply both)";
        }
    }
    GltfJson root = {{"asset", {{"version", "2.0"}, {"generator", options.generator}, {"extras", std::move(asset_extras)}}}};
    GltfJson extensions_used = GltfJson::array();
    if (uses_strength) extensions_used.push_back("KHR_materials_emissive_strength");
    if (uses_lightmap) extensions_used.push_back("MOZ_lightmap");
    if (!lights.empty()) extensions_used.push_back("KHR_lights_punctual");
    // Used, not required: a loader without them still shows the meshes (with vertex light).
    if (!extensions_used.empty()) root["extensionsUsed"] = std::move(extensions_used);
    if (!lights.empty()) root["extensions"] = {{"KHR_lights_punctual", {{"lights", std::move(lights)}}}};
    root["scene"] = 0;
    root["scenes"] = GltfJson::array({{{"name", scene.name}, {"nodes", std::move(node_indices)}}});
    root["nodes"] = std::move(lists.nodes);
    root["meshes"] = std::move(lists.meshes);
    if (!cameras.empty()) root["cameras"] = std::move(cameras);
    if (!materials.empty()) root["materials"] = std::move(materials);
    if (!textures.textures.empty()) {
        root["textures"] = std::move(textures.textures);
        root["images"] = std::move(textures.images);
        root["samplers"] = std::move(textures.samplers);
    }
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
