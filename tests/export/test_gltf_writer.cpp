// The .glb writer on a literal scene: the container, the JSON chunk parsed back, and every
// attribute decoded from the BIN chunk compared with what went in (exact: floats are copied).
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "export/gltf_writer.h"
#include "export/hash.h"
#include "export/lightmap_png.h"
#include "scene/texture_image.h"

using namespace radbake;

namespace {

uint32_t u32At(const std::string& bytes, size_t offset) {
    uint32_t value = 0;
    std::memcpy(&value, bytes.data() + offset, 4);
    return value;
}

// Two meshes that draw and one without triangles (which the writer skips).
Scene literalScene() {
    Scene scene;
    scene.name = "literal";
    Material floor;
    floor.name = "floor";
    floor.reflectance = Vec3(0.5f, 0.6f, 0.7f);
    Material lamp;
    lamp.name = "lamp \"bright\"";
    lamp.reflectance = Vec3(0.1f);
    lamp.emission = Vec3(8.0f, 4.0f, 0.5f);
    scene.materials = {floor, lamp};

    Mesh a;
    a.name = "floor";
    a.positions = {{0, 0, 0}, {2, 0, 0}, {2, 0, 1}, {0, 0, 1}};
    a.triangles = {{0, 3, 2}, {0, 2, 1}};  // both face +Y
    a.triangle_polygon = {0, 0};
    a.polygon_count = 1;
    a.material = 0;
    Mesh b;
    b.name = "lamp";
    b.positions = {{0.25f, 1, 0.25f}, {0.75f, 1, 0.25f}, {0.5f, 1, 0.75f}};
    b.normals = {{0, -2, 0}, {0, -2, 0}, {0, -0.5f, 0}};  // not unit: the writer normalises
    b.triangles = {{0, 1, 2}};
    b.triangle_polygon = {0};
    b.polygon_count = 1;
    b.material = 1;
    Mesh empty;
    empty.name = "empty";
    scene.meshes = {a, b, empty};
    return scene;
}

VertexBake literalBake() {
    VertexBake bake;
    bake.values = {{{0.1f, 0.2f, 0.3f}, {1.5f, 2.0f, 3.0f}, {4, 5, 6}, {0, 0, 0}},
                   {{7, 8, 9}, {10, 11, 12}, {13, 14, 15}},
                   {}};
    return bake;
}

struct Glb {
    nlohmann::json json;
    std::string bin;
};

Glb splitGlb(const std::string& bytes) {
    REQUIRE(bytes.size() >= 20);
    CHECK(u32At(bytes, 0) == 0x46546C67u);
    CHECK(u32At(bytes, 4) == 2u);
    CHECK(u32At(bytes, 8) == bytes.size());
    CHECK(bytes.size() % 4 == 0);
    const uint32_t json_length = u32At(bytes, 12);
    CHECK(u32At(bytes, 16) == 0x4E4F534Au);
    CHECK(json_length % 4 == 0);
    REQUIRE(20 + json_length + 8 <= bytes.size());
    Glb glb;
    glb.json = nlohmann::json::parse(bytes.substr(20, json_length));
    const size_t bin_header = 20 + json_length;
    const uint32_t bin_length = u32At(bytes, bin_header);
    CHECK(u32At(bytes, bin_header + 4) == 0x004E4942u);
    CHECK(bin_length % 4 == 0);
    CHECK(bin_header + 8 + bin_length == bytes.size());
    glb.bin = bytes.substr(bin_header + 8, bin_length);
    return glb;
}

// Reads accessor `index` as floats (or uint32 for indices) through its buffer view.
template <typename T>
std::vector<T> readAccessor(const Glb& glb, size_t index, size_t components) {
    const nlohmann::json& accessor = glb.json.at("accessors").at(index);
    const nlohmann::json& view = glb.json.at("bufferViews").at(accessor.at("bufferView").get<size_t>());
    const size_t count = accessor.at("count").get<size_t>() * components;
    const size_t offset = view.at("byteOffset").get<size_t>();
    REQUIRE(view.at("byteLength").get<size_t>() == count * sizeof(T));
    REQUIRE(offset + count * sizeof(T) <= glb.bin.size());
    std::vector<T> out(count);
    std::memcpy(out.data(), glb.bin.data() + offset, count * sizeof(T));
    return out;
}

}  // namespace

TEST_CASE("glb container, JSON chunk and buffer layout") {
    Diagnostics diagnostics;
    const std::string bytes = encodeGlb(literalScene(), literalBake(), {"radbake test"}, diagnostics);
    CHECK_FALSE(diagnostics.hasErrors());
    const Glb glb = splitGlb(bytes);
    const nlohmann::json& json = glb.json;

    CHECK(json.at("asset").at("version").get<std::string>() == "2.0");
    CHECK(json.at("asset").at("generator").get<std::string>() == "radbake test");
    CHECK(json.at("meshes").size() == 2);  // the mesh without triangles is left out
    CHECK(json.at("nodes").size() == 2);
    CHECK(json.at("scenes").at(0).at("nodes").size() == 2);
    CHECK(json.at("materials").size() == 2);
    CHECK(json.at("accessors").size() == 10);  // 5 per drawn mesh
    CHECK(json.at("bufferViews").size() == 10);

    // Floor: 4 vertices * 4 attributes * 12 bytes + 6 indices * 4; lamp: 3 * 4 * 12 + 3 * 4.
    const size_t expected_bytes = 4 * 4 * 12 + 6 * 4 + 3 * 4 * 12 + 3 * 4;
    CHECK(json.at("buffers").at(0).at("byteLength").get<size_t>() == expected_bytes);
    CHECK(glb.bin.size() == expected_bytes);  // already a multiple of 4: no padding
    size_t view_sum = 0;
    for (const nlohmann::json& view : json.at("bufferViews")) {
        CHECK(view.at("byteOffset").get<size_t>() % 4 == 0);
        CHECK(view.at("byteOffset").get<size_t>() == view_sum);  // tightly packed, in order
        view_sum += view.at("byteLength").get<size_t>();
    }
    CHECK(view_sum == expected_bytes);
}

TEST_CASE("glb attributes decode back to the scene and the bake") {
    Diagnostics diagnostics;
    const Scene scene = literalScene();
    const VertexBake bake = literalBake();
    const Glb glb = splitGlb(encodeGlb(scene, bake, {}, diagnostics));
    const nlohmann::json& json = glb.json;

    for (size_t m = 0; m < 2; ++m) {
        const Mesh& mesh = scene.meshes[m];
        const nlohmann::json& primitive = json.at("meshes").at(m).at("primitives").at(0);
        CHECK(json.at("meshes").at(m).at("name").get<std::string>() == mesh.name);
        CHECK(primitive.at("mode").get<size_t>() == 4);
        CHECK(primitive.at("material").get<size_t>() == mesh.material);
        const nlohmann::json& attributes = primitive.at("attributes");

        const size_t position_index = attributes.at("POSITION").get<size_t>();
        const nlohmann::json& position_accessor = json.at("accessors").at(position_index);
        CHECK(position_accessor.at("componentType").get<size_t>() == 5126);
        CHECK(position_accessor.at("type").get<std::string>() == "VEC3");
        CHECK(position_accessor.at("count").get<size_t>() == mesh.positions.size());
        const std::vector<float> positions = readAccessor<float>(glb, position_index, 3);
        Vec3 lo(1e30f), hi(-1e30f);
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            CHECK(positions[3 * v + 0] == mesh.positions[v].x);
            CHECK(positions[3 * v + 1] == mesh.positions[v].y);
            CHECK(positions[3 * v + 2] == mesh.positions[v].z);
            lo = glm::min(lo, mesh.positions[v]);
            hi = glm::max(hi, mesh.positions[v]);
        }
        for (int k = 0; k < 3; ++k) {
            CHECK(position_accessor.at("min").at(k).get<double>() == doctest::Approx(lo[k]).epsilon(1e-8));
            CHECK(position_accessor.at("max").at(k).get<double>() == doctest::Approx(hi[k]).epsilon(1e-8));
        }

        const std::vector<float> colors = readAccessor<float>(glb, attributes.at("_RADBAKE_LIGHT").get<size_t>(), 3);
        for (size_t v = 0; v < mesh.positions.size(); ++v)
            for (int k = 0; k < 3; ++k) CHECK(colors[3 * v + k] == bake.values[m][v][k]);

        const std::vector<float> normals = readAccessor<float>(glb, attributes.at("NORMAL").get<size_t>(), 3);
        const float expected_y = m == 0 ? 1.0f : -1.0f;  // floor: from its faces; lamp: given, normalised
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            CHECK(normals[3 * v + 0] == 0.0f);
            CHECK(normals[3 * v + 1] == expected_y);
            CHECK(normals[3 * v + 2] == 0.0f);
        }

        const nlohmann::json& index_accessor = json.at("accessors").at(primitive.at("indices").get<size_t>());
        CHECK(index_accessor.at("componentType").get<size_t>() == 5125);
        const std::vector<uint32_t> indices = readAccessor<uint32_t>(glb, primitive.at("indices").get<size_t>(), 1);
        REQUIRE(indices.size() == 3 * mesh.triangles.size());
        for (size_t t = 0; t < mesh.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) CHECK(indices[3 * t + k] == mesh.triangles[t][k]);
    }
}

TEST_CASE("glb materials: base colour, emission and KHR_materials_emissive_strength") {
    Diagnostics diagnostics;
    Scene scene = literalScene();
    const Glb glb = splitGlb(encodeGlb(scene, literalBake(), {}, diagnostics));
    const nlohmann::json& materials = glb.json.at("materials");

    const nlohmann::json& floor = materials.at(0);
    CHECK(floor.at("name").get<std::string>() == "floor");
    CHECK(floor.at("pbrMetallicRoughness").at("baseColorFactor").at(0).get<double>() == doctest::Approx(0.5));
    CHECK(floor.at("pbrMetallicRoughness").at("baseColorFactor").at(2).get<double>() == doctest::Approx(0.7));
    CHECK(floor.at("pbrMetallicRoughness").at("baseColorFactor").at(3).get<double>() == 1.0);
    CHECK(floor.at("pbrMetallicRoughness").at("metallicFactor").get<double>() == 0.0);
    CHECK_FALSE(floor.contains("emissiveFactor"));

    const nlohmann::json& lamp = materials.at(1);
    CHECK(lamp.at("name").get<std::string>() == "lamp \"bright\"");  // escaped in JSON, read back intact
    CHECK(lamp.at("emissiveFactor").at(0).get<double>() == 1.0);
    CHECK(lamp.at("emissiveFactor").at(1).get<double>() == 0.5);
    CHECK(lamp.at("emissiveFactor").at(2).get<double>() == 0.0625);
    CHECK(lamp.at("extensions").at("KHR_materials_emissive_strength").at("emissiveStrength").get<double>() == 8.0);
    REQUIRE(glb.json.at("extensionsUsed").size() == 1);
    CHECK(glb.json.at("extensionsUsed").at(0).get<std::string>() == "KHR_materials_emissive_strength");

    // Emission within [0, 1] needs no extension.
    scene.materials[1].emission = Vec3(0.25f, 1.0f, 0.0f);
    const Glb dim = splitGlb(encodeGlb(scene, literalBake(), {}, diagnostics));
    CHECK_FALSE(dim.json.contains("extensionsUsed"));
    CHECK(dim.json.at("materials").at(1).at("emissiveFactor").at(0).get<double>() == 0.25);
    CHECK_FALSE(dim.json.at("materials").at(1).contains("extensions"));
}

TEST_CASE("glb writer refuses a bake that does not match the scene") {
    Diagnostics diagnostics;
    VertexBake bake = literalBake();
    bake.values[1].pop_back();
    CHECK(encodeGlb(literalScene(), bake, {}, diagnostics).empty());
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].message == "internal: baked values do not match the vertices of mesh 'lamp'");
}

TEST_CASE("glb writer replaces non-finite baked values by 0 with one warning") {
    Diagnostics diagnostics;
    VertexBake bake = literalBake();
    bake.values[0][1].y = std::numeric_limits<float>::quiet_NaN();
    bake.values[1][2].x = std::numeric_limits<float>::infinity();
    const Glb glb = splitGlb(encodeGlb(literalScene(), bake, {}, diagnostics));
    CHECK(diagnostics.warningCount() == 1);
    const std::vector<float> colors =
        readAccessor<float>(glb, glb.json.at("meshes").at(0).at("primitives").at(0).at("attributes").at("_RADBAKE_LIGHT").get<size_t>(), 3);
    CHECK(colors[3 * 1 + 0] == 0.0f);  // the whole vertex value is zeroed
    CHECK(colors[3 * 1 + 1] == 0.0f);
    CHECK(colors[3 * 2 + 0] == 4.0f);
}

TEST_CASE("COLOR_0 is the baked value clamped to [0, 1], as glTF requires; _RADBAKE_LIGHT is exact") {
    Diagnostics diagnostics;
    const VertexBake bake = literalBake();
    const Glb glb = splitGlb(encodeGlb(literalScene(), bake, {"radbake test"}, diagnostics));
    for (size_t m = 0; m < 2; ++m) {
        const nlohmann::json& attributes = glb.json.at("meshes").at(m).at("primitives").at(0).at("attributes");
        CHECK_FALSE(attributes.contains("TEXCOORD_0"));  // no lightmaps, no UVs
        const std::vector<float> color = readAccessor<float>(glb, attributes.at("COLOR_0").get<size_t>(), 3);
        const std::vector<float> light = readAccessor<float>(glb, attributes.at("_RADBAKE_LIGHT").get<size_t>(), 3);
        REQUIRE(color.size() == 3 * bake.values[m].size());
        for (size_t v = 0; v < bake.values[m].size(); ++v)
            for (int k = 0; k < 3; ++k) {
                CHECK(light[3 * v + k] == bake.values[m][v][k]);
                CHECK(color[3 * v + k] == std::clamp(bake.values[m][v][k], 0.0f, 1.0f));
            }
    }
}

namespace {

// Lightmap meshes for literalScene(): the floor's two triangles in two charts on two
// atlases (the second triangle cut at the midpoint of its edge 0-1), the lamp in one chart
// fanned around its centroid, the empty mesh without charts.
LightmapFiles literalLightmaps() {
    LightmapFiles files;
    files.atlas_files = {"lightmaps/literal_0.exr", "lightmaps/literal_1.exr"};
    LightmapMesh floor;
    const Scene scene = literalScene();
    const std::vector<Vec3>& p = scene.meshes[0].positions;
    // Chart on atlas 1: source triangle 0 = {0, 3, 2}.
    floor.positions = {p[0], p[3], p[2]};
    floor.uv = {{0.5f, 0.0f}, {0.5f, 0.25f}, {1.0f, 0.25f}};
    floor.atlas = {1, 1, 1};
    floor.source_corners = {{0, 3, 2}, {0, 3, 2}, {0, 3, 2}};
    floor.barycentric = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    floor.triangles = {{0, 1, 2}};
    floor.source_triangle = {0};
    // Chart on atlas 0: source triangle 1 = {0, 2, 1}, cut at m = midpoint of 0-1.
    const uint32_t b = 3;
    floor.positions.insert(floor.positions.end(), {p[0], 0.5f * (p[0] + p[1]), p[1], p[2]});
    floor.uv.insert(floor.uv.end(), {{0.0f, 0.0f}, {0.125f, 0.0f}, {0.25f, 0.0f}, {0.25f, 0.125f}});
    floor.atlas.insert(floor.atlas.end(), {0, 0, 0, 0});
    floor.source_corners.insert(floor.source_corners.end(), {{0, 2, 1}, {0, 2, 1}, {0, 2, 1}, {0, 2, 1}});
    floor.barycentric.insert(floor.barycentric.end(), {{1, 0, 0}, {0.5f, 0, 0.5f}, {0, 0, 1}, {0, 1, 0}});
    floor.triangles.insert(floor.triangles.end(), {{b + 0, b + 3, b + 1}, {b + 1, b + 3, b + 2}});
    floor.source_triangle.insert(floor.source_triangle.end(), {1, 1});

    LightmapMesh lamp;
    const std::vector<Vec3>& q = scene.meshes[1].positions;
    lamp.positions = {(q[0] + q[1] + q[2]) / 3.0f, q[0], q[1], q[2]};
    lamp.uv = {{0.75f, 0.75f}, {0.5f, 0.5f}, {1.0f, 0.5f}, {0.75f, 1.0f}};
    lamp.atlas = {0, 0, 0, 0};
    lamp.source_corners = {{0, 1, 2}, {0, 1, 2}, {0, 1, 2}, {0, 1, 2}};
    lamp.barycentric = {Vec3(1.0f / 3.0f), {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    lamp.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}};
    lamp.source_triangle = {0, 0, 0};
    files.meshes = {floor, lamp, LightmapMesh{}};
    return files;
}

std::vector<std::string> strings(const nlohmann::json& list) {
    std::vector<std::string> out;
    for (const nlohmann::json& item : list) out.push_back(item.get<std::string>());
    return out;
}

}  // namespace

TEST_CASE("glb with lightmaps: one primitive per atlas, TEXCOORD_1, interpolated COLOR_0, extras") {
    const Scene scene = literalScene();
    const VertexBake bake = literalBake();
    const LightmapFiles lightmaps = literalLightmaps();
    GltfOptions options;
    options.lightmaps = &lightmaps;
    Diagnostics diagnostics;
    const Glb glb = splitGlb(encodeGlb(scene, bake, options, diagnostics));
    CHECK(diagnostics.all().empty());
    const nlohmann::json& json = glb.json;
    CHECK(strings(json.at("asset").at("extras").at("radbake_lightmaps")) == lightmaps.atlas_files);
    REQUIRE(json.at("meshes").size() == 2);

    // Per scene mesh: the atlases its primitives should cover, in order.
    const std::vector<std::vector<int>> expected_atlases = {{0, 1}, {0}};
    for (size_t m = 0; m < 2; ++m) {
        CAPTURE(m);
        const nlohmann::json& mesh_json = json.at("meshes").at(m);
        const LightmapMesh& lm = lightmaps.meshes[m];
        std::vector<std::string> expected_files;
        for (int atlas : expected_atlases[m]) expected_files.push_back(lightmaps.atlas_files[atlas]);
        CHECK(strings(mesh_json.at("extras").at("radbake_lightmaps")) == expected_files);
        REQUIRE(mesh_json.at("primitives").size() == expected_atlases[m].size());

        for (size_t p = 0; p < expected_atlases[m].size(); ++p) {
            CAPTURE(p);
            const int atlas = expected_atlases[m][p];
            const nlohmann::json& primitive = mesh_json.at("primitives").at(p);
            CHECK(primitive.at("extras").at("radbake_lightmap").get<std::string>() == lightmaps.atlas_files[atlas]);
            CHECK(primitive.at("extras").at("radbake_lightmap_index").get<size_t>() == static_cast<size_t>(atlas));
            // A material of its own per (scene material, atlas), naming its atlas.
            const nlohmann::json& material = json.at("materials").at(primitive.at("material").get<size_t>());
            // The floor's material spans two atlases: named apart; the lamp's keeps its name.
            const std::string& source_name = scene.materials[scene.meshes[m].material].name;
            CHECK(material.at("name").get<std::string>() ==
                  (m == 0 ? source_name + " (lightmap " + std::to_string(atlas) + ")" : source_name));
            CHECK(material.at("extras").at("radbake_lightmap").get<std::string>() == lightmaps.atlas_files[atlas]);
            CHECK_FALSE((material.contains("extensions") && material.at("extensions").contains("MOZ_lightmap")));
            const nlohmann::json& attributes = primitive.at("attributes");
            CHECK(attributes.at("TEXCOORD_0").get<size_t>() == attributes.at("TEXCOORD_1").get<size_t>());

            // Brute force: the lightmap triangles on this atlas, in order, against the decoded ones.
            std::vector<uint32_t> expected_corners;
            for (const UVec3& t : lm.triangles)
                if (lm.atlas[t.x] == atlas) expected_corners.insert(expected_corners.end(), {t.x, t.y, t.z});
            const std::vector<uint32_t> indices = readAccessor<uint32_t>(glb, primitive.at("indices").get<size_t>(), 1);
            REQUIRE(indices.size() == expected_corners.size());
            std::vector<uint32_t> distinct = expected_corners;
            std::sort(distinct.begin(), distinct.end());
            distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());

            const size_t position_index = attributes.at("POSITION").get<size_t>();
            const nlohmann::json& position_accessor = json.at("accessors").at(position_index);
            CHECK(position_accessor.at("count").get<size_t>() == distinct.size());  // only this atlas's vertices
            const std::vector<float> positions = readAccessor<float>(glb, position_index, 3);
            const std::vector<float> normals = readAccessor<float>(glb, attributes.at("NORMAL").get<size_t>(), 3);
            const std::vector<float> colors = readAccessor<float>(glb, attributes.at("_RADBAKE_LIGHT").get<size_t>(), 3);
            const std::vector<float> uvs = readAccessor<float>(glb, attributes.at("TEXCOORD_1").get<size_t>(), 2);
            REQUIRE(uvs.size() == 2 * distinct.size());
            for (size_t i = 0; i < indices.size(); ++i) {
                const uint32_t out = indices[i], in = expected_corners[i];
                REQUIRE(out < distinct.size());
                for (int k = 0; k < 3; ++k) {
                    CHECK(positions[3 * out + k] == lm.positions[in][k]);
                    const float expected_color = interpolateSource(lm, in, bake.values[m])[k];
                    CHECK(colors[3 * out + k] == doctest::Approx(expected_color).epsilon(1e-6));
                }
                CHECK(uvs[2 * out] == lm.uv[in].x);
                CHECK(uvs[2 * out + 1] == lm.uv[in].y);
                // Floor: no normals given, so the face normal (+Y); lamp: its own normals (-Y).
                CHECK(normals[3 * out + 1] == (m == 0 ? 1.0f : -1.0f));
            }
            Vec3 lo(1e30f), hi(-1e30f);
            for (uint32_t v : distinct) {
                lo = glm::min(lo, lm.positions[v]);
                hi = glm::max(hi, lm.positions[v]);
            }
            for (int k = 0; k < 3; ++k) {
                CHECK(position_accessor.at("min").at(k).get<double>() == doctest::Approx(lo[k]).epsilon(1e-8));
                CHECK(position_accessor.at("max").at(k).get<double>() == doctest::Approx(hi[k]).epsilon(1e-8));
            }
            const nlohmann::json& uv_accessor = json.at("accessors").at(attributes.at("TEXCOORD_1").get<size_t>());
            CHECK(uv_accessor.at("type").get<std::string>() == "VEC2");
            for (int k = 0; k < 2; ++k) {
                CHECK(uv_accessor.at("min").at(k).get<double>() >= 0.0);
                CHECK(uv_accessor.at("max").at(k).get<double>() <= 1.0);
            }
        }
    }
    // Closed-form spot checks: the floor's cut vertex and the lamp's centroid.
    const std::vector<float> floor_colors =
        readAccessor<float>(glb, json.at("meshes").at(0).at("primitives").at(0).at("attributes").at("_RADBAKE_LIGHT").get<size_t>(), 3);
    CHECK(floor_colors[3 * 2 + 0] == doctest::Approx(0.8));  // (0.1 + 1.5) / 2; third new vertex is m
    CHECK(floor_colors[3 * 2 + 2] == doctest::Approx(1.65));
    const std::vector<float> lamp_colors =
        readAccessor<float>(glb, json.at("meshes").at(1).at("primitives").at(0).at("attributes").at("_RADBAKE_LIGHT").get<size_t>(), 3);
    CHECK(lamp_colors[0] == doctest::Approx(10.0));
    CHECK(lamp_colors[1] == doctest::Approx(11.0));
    CHECK(lamp_colors[2] == doctest::Approx(12.0));
}

TEST_CASE("glb with lightmaps writes a mesh without charts as before, and refuses inconsistent lightmaps") {
    const Scene scene = literalScene();
    LightmapFiles lightmaps = literalLightmaps();
    lightmaps.meshes[1] = LightmapMesh{};  // the lamp has no charts
    GltfOptions options;
    options.lightmaps = &lightmaps;
    Diagnostics diagnostics;
    const Glb with = splitGlb(encodeGlb(scene, literalBake(), options, diagnostics));
    const Glb without = splitGlb(encodeGlb(scene, literalBake(), {}, diagnostics));
    const nlohmann::json& lamp = with.json.at("meshes").at(1);
    CHECK_FALSE(lamp.contains("extras"));
    REQUIRE(lamp.at("primitives").size() == 1);
    CHECK_FALSE(lamp.at("primitives").at(0).at("attributes").contains("TEXCOORD_1"));
    CHECK(lamp.at("primitives").at(0).at("attributes").size() == 4);
    const std::vector<float> colors = readAccessor<float>(with, lamp.at("primitives").at(0).at("attributes").at("_RADBAKE_LIGHT").get<size_t>(), 3);
    const std::vector<float> colors_before =
        readAccessor<float>(without, without.json.at("meshes").at(1).at("primitives").at(0).at("attributes").at("_RADBAKE_LIGHT").get<size_t>(), 3);
    CHECK(colors == colors_before);
    CHECK(diagnostics.all().empty());

    lightmaps = literalLightmaps();
    lightmaps.meshes[0].atlas[4] = 2;  // no such atlas file
    CHECK(encodeGlb(scene, literalBake(), options, diagnostics).empty());
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].message == "internal: lightmap mesh of 'floor' is inconsistent: an atlas index has no file");
    lightmaps = literalLightmaps();
    lightmaps.meshes.pop_back();
    CHECK(encodeGlb(scene, literalBake(), options, diagnostics).empty());
    REQUIRE(diagnostics.errorCount() == 2);
    CHECK(diagnostics.all()[1].message == "internal: lightmap meshes for 2 meshes, scene has 3");
}

TEST_CASE("glb cameras: each Viewpoint becomes a perspective camera on a node of the scene") {
    Scene scene = literalScene();
    Camera view;
    view.name = "Entrance";
    view.position = Vec3(1.0f, 2.0f, 3.0f);
    view.orientation = glm::angleAxis(0.5f, glm::normalize(Vec3(0.0f, 1.0f, 1.0f)));
    view.field_of_view = 0.6f;
    scene.cameras.push_back(view);
    scene.cameras.push_back(Camera{});  // unnamed: a name is made up
    Diagnostics diagnostics;
    const Glb glb = splitGlb(encodeGlb(scene, literalBake(), {"radbake test"}, diagnostics));
    CHECK_FALSE(diagnostics.hasErrors());
    const nlohmann::json& json = glb.json;
    REQUIRE(json.at("cameras").size() == 2);
    const nlohmann::json& camera = json.at("cameras").at(0);
    CHECK(camera.at("type") == "perspective");
    CHECK(camera.at("perspective").at("yfov").get<double>() == doctest::Approx(0.6));
    CHECK(camera.at("perspective").at("znear").get<double>() > 0.0);
    CHECK(json.at("cameras").at(1).at("name") == "Viewpoint 1");
    // Mesh nodes first, then one node per camera, all in the scene.
    REQUIRE(json.at("nodes").size() == 4);
    CHECK(json.at("scenes").at(0).at("nodes").size() == 4);
    const nlohmann::json& node = json.at("nodes").at(2);
    CHECK(node.at("name") == "Entrance");
    CHECK(node.at("camera") == 0);
    CHECK(node.at("translation").at(2).get<double>() == doctest::Approx(3.0));
    const Quat q = glm::normalize(view.orientation);
    CHECK(node.at("rotation").at(0).get<double>() == doctest::Approx(q.x));
    CHECK(node.at("rotation").at(3).get<double>() == doctest::Approx(q.w));
    CHECK(json.at("nodes").at(3).at("camera") == 1);
}

namespace {

// One PNG per atlas of literalLightmaps(): a 2 x 1 image with a bright texel of `peak`.
std::vector<LightmapPng> literalPngs(const LightmapFiles& lightmaps) {
    std::vector<LightmapPng> pngs;
    for (size_t k = 0; k < lightmaps.atlas_files.size(); ++k) {
        RgbImage image;
        image.width = 2;
        image.height = 1;
        const float peak = 2.0f + static_cast<float>(k);
        image.rgb = {0.5f, 0.25f, 0.0f, peak, 1.0f, 0.1f};
        LightmapPng png;
        png.file = "lightmaps/literal_" + std::to_string(k) + ".png";
        png.bytes = encodeLightmapPng(image);
        REQUIRE_FALSE(png.bytes.empty());
        pngs.push_back(std::move(png));
    }
    return pngs;
}

// The bytes of image `index` through its buffer view.
std::string imageBytes(const Glb& glb, size_t index) {
    const nlohmann::json& image = glb.json.at("images").at(index);
    CHECK(image.at("mimeType").get<std::string>() == "image/png");
    const nlohmann::json& view = glb.json.at("bufferViews").at(image.at("bufferView").get<size_t>());
    return glb.bin.substr(view.at("byteOffset").get<size_t>(), view.at("byteLength").get<size_t>());
}

}  // namespace

TEST_CASE("rgbe8: a texel's brightest channel within 0.4 % at any scale, the others within half its step") {
    for (double scale = 1e-30; scale < 1e30; scale *= 7.3) {
        const float r = static_cast<float>(scale), g = static_cast<float>(0.37 * scale), b = static_cast<float>(0.002 * scale);
        CAPTURE(scale);
        const std::array<uint8_t, 4> texel = encodeRgbe(r, g, b);
        REQUIRE(texel[3] > 0);
        CHECK(texel[0] >= 128);  // the brightest channel keeps 8 significant bits
        const double step = decodeRgbe(1, texel[3]);  // one code of this texel
        CHECK(std::fabs(decodeRgbe(texel[0], texel[3]) - r) <= 0.5 * step * (1 + 1e-6));
        CHECK(std::fabs(decodeRgbe(texel[1], texel[3]) - g) <= 0.5 * step * (1 + 1e-6));
        CHECK(std::fabs(decodeRgbe(texel[2], texel[3]) - b) <= 0.5 * step * (1 + 1e-6));
        CHECK(step / r < 1.0 / 127.0);  // neighbouring codes of the brightest channel: under 0.8 % apart
    }
    // Just below a power of two the mantissa rounds up to 256: the exponent takes it.
    const std::array<uint8_t, 4> carry = encodeRgbe(0.9999f, 0.0f, 0.0f);
    CHECK(decodeRgbe(carry[0], carry[3]) == doctest::Approx(1.0));
    CHECK(encodeRgbe(0.0f, 0.0f, 0.0f) == std::array<uint8_t, 4>{0, 0, 0, 0});
    CHECK(encodeRgbe(-1.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f) == std::array<uint8_t, 4>{0, 0, 0, 0});
    const std::array<uint8_t, 4> mixed = encodeRgbe(-1.0f, 2.0f, std::numeric_limits<float>::quiet_NaN());
    CHECK(decodeRgbe(mixed[0], mixed[3]) == 0.0f);
    CHECK(decodeRgbe(mixed[1], mixed[3]) == doctest::Approx(2.0));
    CHECK(decodeRgbe(mixed[2], mixed[3]) == 0.0f);
    CHECK(decodeRgbe(0, 0) == 0.0f);
    CHECK(encodeRgbe(std::numeric_limits<float>::infinity(), 0.0f, 0.0f)[3] == 255);
}

TEST_CASE("the lightmap PNG: RGBA bytes of rgbe8 that a PNG reader reads back, the encoding in a tEXt chunk") {
    RgbImage image;
    image.width = 3;
    image.height = 2;
    image.rgb = {0.0f, 1.0f, 4.0f,   2.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),  3.0f, 0.5f, 0.01f,
                 1e-4f, 2e-4f, 3e-4f, 15.9f, 15.9f, 15.9f, 0.0f, 0.0f, 0.0f};
    const std::string png = encodeLightmapPng(image);
    REQUIRE(png.size() > 33);
    CHECK(png.compare(12, 4, "IHDR") == 0);
    CHECK(static_cast<int>(png[24]) == 8);  // bit depth
    CHECK(static_cast<int>(png[25]) == 6);  // RGBA
    CHECK(png.find(std::string("tEXtradbake:encoding") + '\0' + "rgbe8") != std::string::npos);
    // A valid PNG (CRCs, zlib stream, Sub filters): stb_image reads the bytes back.
    TextureRef ref;
    ref.path = "literal.png";
    ref.embedded = std::make_shared<std::string>(png);
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;
    std::string error;
    REQUIRE(readImageRgba8(ref, width, height, rgba, error));
    REQUIRE(width == 3);
    REQUIRE(height == 2);
    for (size_t p = 0; p < 6; ++p) {
        CAPTURE(p);
        const float* rgb = &image.rgb[3 * p];
        const auto clean = [](float v) { return v > 0.0f ? v : 0.0f; };  // negative and NaN read 0
        const std::array<uint8_t, 4> texel = encodeRgbe(rgb[0], rgb[1], rgb[2]);
        const float peak = std::max({clean(rgb[0]), clean(rgb[1]), clean(rgb[2])});
        for (int c = 0; c < 4; ++c) CHECK(rgba[4 * p + c] == texel[c]);
        for (int c = 0; c < 3; ++c)
            CHECK(std::fabs(decodeRgbe(rgba[4 * p + c], rgba[4 * p + 3]) - clean(rgb[c])) <= peak / 256.0f);
    }
    CHECK(encodeLightmapPng(RgbImage{}).empty());
}

TEST_CASE("glb lightmap texture: each lightmapped material reaches its atlas's PNG through MOZ_lightmap, texCoord 1") {
    const Scene scene = literalScene();
    const LightmapFiles lightmaps = literalLightmaps();
    const std::vector<LightmapPng> pngs = literalPngs(lightmaps);
    GltfOptions options;
    options.lightmaps = &lightmaps;
    options.lightmap_textures = &pngs;
    Diagnostics diagnostics;
    const Glb glb = splitGlb(encodeGlb(scene, literalBake(), options, diagnostics));
    CHECK(diagnostics.all().empty());
    const nlohmann::json& json = glb.json;
    const std::vector<std::string> used = strings(json.at("extensionsUsed"));
    CHECK(std::find(used.begin(), used.end(), "MOZ_lightmap") != used.end());
    CHECK_FALSE(json.contains("extensionsRequired"));  // a loader without it still draws the meshes

    const std::vector<std::vector<int>> expected_atlases = {{0, 1}, {0}};
    for (size_t m = 0; m < 2; ++m)
        for (size_t p = 0; p < expected_atlases[m].size(); ++p) {
            CAPTURE(m);
            CAPTURE(p);
            const int atlas = expected_atlases[m][p];
            const nlohmann::json& primitive = json.at("meshes").at(m).at("primitives").at(p);
            CHECK(primitive.at("attributes").contains("TEXCOORD_1"));
            CHECK_FALSE(primitive.at("attributes").contains("COLOR_0"));  // the lightmap lights it, not COLOR_0 too
            CHECK(primitive.at("attributes").contains("_RADBAKE_LIGHT"));
            const nlohmann::json& material = json.at("materials").at(primitive.at("material").get<size_t>());
            const nlohmann::json& extension = material.at("extensions").at("MOZ_lightmap");
            CHECK(extension.at("texCoord").get<int>() == 1);
            CHECK(extension.at("intensity").get<double>() == doctest::Approx(kPi));
            const nlohmann::json& texture = json.at("textures").at(extension.at("index").get<size_t>());
            CHECK(imageBytes(glb, texture.at("source").get<size_t>()) == pngs[atlas].bytes);
            const nlohmann::json& sampler = json.at("samplers").at(texture.at("sampler").get<size_t>());
            CHECK(sampler.at("wrapS").get<int>() == 33071);  // clamped, not repeating
            CHECK(sampler.at("minFilter").get<int>() == 9729);  // no mipmaps across charts
            CHECK(material.at("extras").at("radbake_lightmap_png").get<std::string>() == pngs[atlas].file);
            CHECK(material.at("extras").at("radbake_lightmap_encoding").get<std::string>() == "rgbe8");
        }
    // One image per atlas, however many materials use it.
    CHECK(json.at("images").size() == 2);
    CHECK(strings(json.at("asset").at("extras").at("radbake_lightmap_pngs")) ==
          std::vector<std::string>{pngs[0].file, pngs[1].file});

    std::vector<LightmapPng> short_list = pngs;
    short_list.pop_back();
    options.lightmap_textures = &short_list;
    CHECK(encodeGlb(scene, literalBake(), options, diagnostics).empty());
    CHECK(diagnostics.errorCount() == 1);
}

TEST_CASE("glb: one material per (source material, atlas), shared by the primitives of one pair") {
    Scene scene = literalScene();
    scene.meshes[1].material = 0;  // the lamp now shares the floor's material, on atlas 0
    const LightmapFiles lightmaps = literalLightmaps();
    GltfOptions options;
    options.lightmaps = &lightmaps;
    Diagnostics diagnostics;
    const Glb glb = splitGlb(encodeGlb(scene, literalBake(), options, diagnostics));
    const nlohmann::json& meshes = glb.json.at("meshes");
    const size_t floor_0 = meshes.at(0).at("primitives").at(0).at("material").get<size_t>();
    const size_t floor_1 = meshes.at(0).at("primitives").at(1).at("material").get<size_t>();
    const size_t lamp_0 = meshes.at(1).at("primitives").at(0).at("material").get<size_t>();
    CHECK(floor_0 != floor_1);  // one mesh over two atlases: two materials
    CHECK(lamp_0 == floor_0);   // same material, same atlas: one
    const nlohmann::json& materials = glb.json.at("materials");
    CHECK(materials.size() == 2);  // the scene's 'lamp' material is used by no primitive
    CHECK(materials.at(floor_0).at("name").get<std::string>() == "floor (lightmap 0)");
    CHECK(materials.at(floor_1).at("name").get<std::string>() == "floor (lightmap 1)");
    CHECK(materials.at(floor_1).at("extras").at("radbake_lightmap_index").get<int>() == 1);
    // Both keep the source material's colour.
    for (const size_t i : {floor_0, floor_1})
        CHECK(materials.at(i).at("pbrMetallicRoughness").at("baseColorFactor").at(1).get<double>() == doctest::Approx(0.6));
}

TEST_CASE("glb lights: none by default; with export_lights, KHR_lights_punctual on nodes, marked as baked") {
    Scene scene = literalScene();
    Light point;
    point.type = LightType::Point;
    point.position = Vec3(1.0f, 2.0f, 3.0f);
    point.color = Vec3(1.0f, 0.5f, 0.25f);
    point.intensity = 0.8f;
    point.radius = 7.0f;
    Light spot;
    spot.type = LightType::Spot;
    spot.direction = Vec3(0.0f, -1.0f, 0.0f);
    spot.beam_width = 1.0f;  // wider than the cut-off: VRML's hard edge
    spot.cut_off_angle = 0.5f;
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(Vec3(1.0f, -1.0f, 0.0f));
    Light off = point;
    off.on = false;
    off.location = {"lights.wrl", 12, 3};
    scene.lights = {point, spot, sun, off};

    Diagnostics diagnostics;
    const Glb plain = splitGlb(encodeGlb(scene, literalBake(), {}, diagnostics));
    CHECK_FALSE(plain.json.contains("extensions"));
    CHECK(strings(plain.json.at("extensionsUsed")) == std::vector<std::string>{"KHR_materials_emissive_strength"});
    CHECK(plain.json.at("nodes").size() == 2);
    CHECK(diagnostics.all().empty());

    GltfOptions options;
    options.export_lights = true;
    const Glb glb = splitGlb(encodeGlb(scene, literalBake(), options, diagnostics));
    REQUIRE(diagnostics.warningCount() == 1);  // the light that is off
    CHECK(diagnostics.all()[0].location.line == 12);
    const nlohmann::json& json = glb.json;
    CHECK(strings(json.at("extensionsUsed")) ==
          std::vector<std::string>{"KHR_materials_emissive_strength", "KHR_lights_punctual"});
    const nlohmann::json& lights = json.at("extensions").at("KHR_lights_punctual").at("lights");
    REQUIRE(lights.size() == 3);
    for (const nlohmann::json& light : lights) CHECK(light.at("extras").at("radbake_baked").get<bool>());
    CHECK(lights.at(0).at("type") == "point");
    CHECK(lights.at(0).at("intensity").get<double>() == doctest::Approx(0.8));  // the largest channel, W/sr
    CHECK(lights.at(0).at("color").at(2).get<double>() == doctest::Approx(0.25));
    CHECK(lights.at(0).at("range").get<double>() == doctest::Approx(7.0));
    const nlohmann::json& cone = lights.at(1).at("spot");
    CHECK(cone.at("outerConeAngle").get<double>() == doctest::Approx(0.5));
    CHECK(cone.at("innerConeAngle").get<double>() < cone.at("outerConeAngle").get<double>());
    CHECK(lights.at(2).at("type") == "directional");

    // Mesh nodes, then one node per light that is on, each in the scene.
    REQUIRE(json.at("nodes").size() == 5);
    CHECK(json.at("scenes").at(0).at("nodes").size() == 5);
    for (size_t k = 0; k < 3; ++k)
        CHECK(json.at("nodes").at(2 + k).at("extensions").at("KHR_lights_punctual").at("light").get<size_t>() == k);
    CHECK(json.at("nodes").at(2).at("translation").at(1).get<double>() == doctest::Approx(2.0));
    // The node's rotation turns glTF's light direction (-Z) onto the light's.
    for (const size_t k : {1u, 2u}) {
        const nlohmann::json& r = json.at("nodes").at(2 + k).at("rotation");
        const Quat q(r.at(3).get<float>(), r.at(0).get<float>(), r.at(1).get<float>(), r.at(2).get<float>());
        const Vec3 d = q * Vec3(0.0f, 0.0f, -1.0f);
        const Vec3 expected = k == 1 ? spot.direction : sun.direction;
        CHECK(glm::length(d - expected) < 1e-5f);
    }
}
