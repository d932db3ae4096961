// Source UVs and material textures, end to end on tiny literal files written here (issue 14,
// "keep the asset"): the texture sets the reflectance the solve uses, the glb keeps the UVs
// and embeds the images, a missing texture is one warning and still a dependency.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC  // private copies for the tests
#include <stb/stb_image_write.h>
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb/stb_image.h>

#include "cli_support.h"
#include "radbake.h"

using namespace radbake;
using namespace clitest;

namespace {

// IEC 61966-2-1, written out here so the expectations do not reuse the code under test.
double srgbDecoded(int byte) {
    const double c = byte / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

void writePng(const fs::path& path, int width, int height, int channels, const std::vector<uint8_t>& pixels) {
    REQUIRE(pixels.size() == static_cast<size_t>(width * height * channels));
    REQUIRE(stbi_write_png(path.c_str(), width, height, channels, pixels.data(), width * channels) != 0);
}

// Radiance RGBE stores 0.5 exactly: a linear grey no 8-bit sRGB value hits.
void writeUniformHdr(const fs::path& path, float value) {
    const std::vector<float> rgb(2 * 2 * 3, value);
    REQUIRE(stbi_write_hdr(path.c_str(), 2, 2, 3, rgb.data()) != 0);
}

// The inside of the unit cube, every face one quad facing in, UVs (0,0) (1,0) (1,1) (0,1).
std::string insideCubeObj(const std::string& mtl) {
    return "mtllib " + mtl +
           "\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl wall\n"
           "f 1/1 2/2 3/3 4/4\nf 5/1 8/2 7/3 6/4\nf 1/1 5/2 6/3 2/4\nf 4/1 3/2 7/3 8/4\nf 1/1 4/2 8/3 5/4\n"
           "f 2/1 6/2 7/3 3/4\n";
}

Bake bakeInMemory(const fs::path& scene, Diagnostics& diagnostics) {
    BakeOptions options;  // the default (medium) quality the analytic furnaces are checked at
    options.lightmaps.enabled = false;
    options.threading.threads = 2;
    Progress progress(false);
    return bake(scene.string(), options, progress, diagnostics);
}

size_t countMessages(const Diagnostics& diagnostics, Severity severity, const std::string& part) {
    size_t count = 0;
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == severity && d.message.find(part) != std::string::npos) ++count;
    return count;
}

const Diagnostic* findMessage(const Diagnostics& diagnostics, const std::string& part) {
    for (const Diagnostic& d : diagnostics.all())
        if (d.message.find(part) != std::string::npos) return &d;
    return nullptr;
}

// A glb's JSON and BIN chunk.
struct Glb {
    nlohmann::json root;
    std::string bin;

    explicit Glb(const std::string& bytes) {
        REQUIRE(bytes.size() >= 20);
        uint32_t json_length = 0, bin_length = 0;
        std::memcpy(&json_length, bytes.data() + 12, 4);
        root = nlohmann::json::parse(bytes.substr(20, json_length));
        const size_t bin_at = 20 + json_length;
        REQUIRE(bytes.size() >= bin_at + 8);
        std::memcpy(&bin_length, bytes.data() + bin_at, 4);
        bin = bytes.substr(bin_at + 8, bin_length);
    }
    std::string viewBytes(size_t view_index) const {
        const nlohmann::json& view = root["bufferViews"][view_index];
        return bin.substr(view.value("byteOffset", size_t{0}), view["byteLength"].get<size_t>());
    }
    std::vector<float> floats(size_t accessor_index) const {
        const nlohmann::json& accessor = root["accessors"][accessor_index];
        const std::string bytes = viewBytes(accessor["bufferView"].get<size_t>());
        const size_t components = accessor["type"] == "VEC2" ? 2 : 3;
        std::vector<float> out(accessor["count"].get<size_t>() * components);
        REQUIRE(bytes.size() >= out.size() * 4);
        std::memcpy(out.data(), bytes.data(), out.size() * 4);
        return out;
    }
};

// A floor quad (two polygons side by side, x in [0, 2]) under a lamp, with UVs given here.
void writeFloorScene(const fs::path& dir, const std::string& floor_texture, const std::string& more_mtl = "") {
    writeText(dir / "floor.mtl", "newmtl light\nKd 0 0 0\nKe 2 2 2\nnewmtl floor\nKd 0.8 0.8 0.8\nmap_Kd " +
                                     floor_texture + "\n" + more_mtl);
    writeText(dir / "floor.obj", "mtllib floor.mtl\n"
                                 "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 2 0 1\nv 1 0 1\nv 0 0 1\n"
                                 "v 0.2 1 0.2\nv 1.8 1 0.2\nv 1.8 1 0.8\nv 0.2 1 0.8\n"
                                 "vt 0 0.25\nvt 0.5 0.25\nvt 1 0.25\nvt 1 0.75\nvt 0.5 0.75\nvt 0 0.75\n"
                                 "usemtl floor\nf 1/1 6/6 5/5 2/2\nf 2/2 5/5 4/4 3/3\n"
                                 "usemtl light\nf 7 8 9 10\n");
}

}  // namespace

TEST_CASE("textures: the map_Kd furnace (Kd 1, texture linear 0.5) is the rho = 0.5 furnace, H = 2 pi L_e") {
    const TempDir tmp;
    writeUniformHdr(tmp.path / "grey.hdr", 0.5f);
    writeText(tmp.path / "textured.mtl", "newmtl wall\nKd 1 1 1\nKe 1 1 1\nmap_Kd grey.hdr\n");
    writeText(tmp.path / "textured.obj", insideCubeObj("textured.mtl"));
    writeText(tmp.path / "plain.mtl", "newmtl wall\nKd 0.5 0.5 0.5\nKe 1 1 1\n");
    writeText(tmp.path / "plain.obj", insideCubeObj("plain.mtl"));

    Diagnostics textured_diagnostics, plain_diagnostics;
    const Bake textured = bakeInMemory(tmp.path / "textured.obj", textured_diagnostics);
    const Bake plain = bakeInMemory(tmp.path / "plain.obj", plain_diagnostics);
    REQUIRE(textured.ok());
    REQUIRE(plain.ok());
    // Kd 1 is the texture's factor, not a reflectance >= 1: no clamp warning.
    CHECK(countMessages(textured_diagnostics, Severity::Warning, "") == 0);
    for (const Mesh& mesh : textured.scene->meshes) {
        REQUIRE(mesh.polygon_reflectance.size() == mesh.polygon_count);
        for (const Vec3& rho : mesh.polygon_reflectance) CHECK(rho == Vec3(0.5f));
    }
    // Closed form: H / pi = L_e / (1 - rho) = 2 everywhere (1% at the default quality, as the
    // analytic furnaces), and the very values of the untextured rho = 0.5 furnace.
    REQUIRE(textured.vertices.values.size() == plain.vertices.values.size());
    for (size_t m = 0; m < textured.vertices.values.size(); ++m) {
        REQUIRE(textured.vertices.values[m].size() == plain.vertices.values[m].size());
        for (size_t v = 0; v < textured.vertices.values[m].size(); ++v)
            for (int c = 0; c < 3; ++c) {
                CHECK(textured.vertices.values[m][v][c] == doctest::Approx(2.0).epsilon(0.01));
                CHECK(textured.vertices.values[m][v][c] == doctest::Approx(plain.vertices.values[m][v][c]).epsilon(1e-6));
            }
    }
    CHECK(std::find(textured.scene->input_files.begin(), textured.scene->input_files.end(),
                    (tmp.path / "grey.hdr").lexically_normal().string()) != textured.scene->input_files.end());
}

TEST_CASE("textures: a half-black, half-white map_Kd gives the two polygons it covers their own reflectance") {
    const TempDir tmp;
    writePng(tmp.path / "half.png", 2, 1, 3, {0, 0, 0, 255, 255, 255});  // left texel black, right white
    writeFloorScene(tmp.path, "half.png");
    Diagnostics diagnostics;
    const Bake baked = bakeInMemory(tmp.path / "floor.obj", diagnostics);
    REQUIRE(baked.ok());
    const Mesh* floor = nullptr;
    for (const Mesh& mesh : baked.scene->meshes)
        if (baked.scene->materials[mesh.material].name == "floor") floor = &mesh;
    REQUIRE(floor);
    REQUIRE(floor->polygon_count == 2);
    REQUIRE(floor->polygon_reflectance.size() == 2);
    CHECK(floor->polygon_reflectance[0] == Vec3(0.0f));  // u in [0, 0.5]: black times Kd
    CHECK(floor->polygon_reflectance[1] == Vec3(0.8f));  // u in [0.5, 1]: white times Kd
    // The solve uses them: each root element of the floor has its polygon's reflectance.
    const uint32_t floor_index = static_cast<uint32_t>(floor - baked.scene->meshes.data());
    int roots = 0;
    for (uint32_t i = 0; i < baked.solution->root_count; ++i) {
        const Element& e = baked.solution->elements[i];
        if (e.mesh != floor_index) continue;
        ++roots;
        CHECK(e.reflectance == DVec3(floor->polygon_reflectance[e.polygon]));
    }
    CHECK(roots >= 2);
}

TEST_CASE("textures: the glb keeps the source UVs in TEXCOORD_0, the lightmap's in TEXCOORD_1, and embeds the PNG") {
    const TempDir tmp;
    writePng(tmp.path / "half.png", 2, 1, 3, {0, 0, 0, 255, 255, 255});
    writeFloorScene(tmp.path, "half.png");
    // Where each floor vertex is (x, z) -> its source UV in glTF's convention (u, 1 - v).
    const std::vector<std::pair<Vec2, Vec2>> expected = {{{0, 0}, {0, 0.75f}},   {{1, 0}, {0.5f, 0.75f}},
                                                         {{2, 0}, {1, 0.75f}},   {{2, 1}, {1, 0.25f}},
                                                         {{1, 1}, {0.5f, 0.25f}}, {{0, 1}, {0, 0.25f}}};
    for (const bool lightmaps : {false, true}) {
        CAPTURE(lightmaps);
        const fs::path out = tmp.path / (lightmaps ? "with" : "without");
        const RunResult run = runRadbake("bake " + quote(tmp.path / "floor.obj") + " -o " + quote(out) +
                                         " --quality draft -q" + (lightmaps ? "" : " --no-lightmaps"));
        INFO(run.output);
        REQUIRE(run.exit_code == 0);
        const Glb glb(readBytes(out / "floor.glb"));
        // The floor material's base colour texture is the PNG, byte for byte, through texCoord 0.
        const nlohmann::json* floor_material = nullptr;
        for (const auto& material : glb.root["materials"])
            if (material["name"] == "floor") floor_material = &material;
        REQUIRE(floor_material);
        const nlohmann::json& info = (*floor_material)["pbrMetallicRoughness"]["baseColorTexture"];
        CHECK(info.value("texCoord", 0) == 0);
        const nlohmann::json& texture = glb.root["textures"][info["index"].get<size_t>()];
        const nlohmann::json& image = glb.root["images"][texture["source"].get<size_t>()];
        CHECK(image["mimeType"] == "image/png");
        CHECK(glb.viewBytes(image["bufferView"].get<size_t>()) == readBytes(tmp.path / "half.png"));
        CHECK(glb.root["samplers"][texture["sampler"].get<size_t>()]["wrapS"] == 10497);

        size_t floor_vertices = 0;
        for (const auto& mesh : glb.root["meshes"])
            for (const auto& primitive : mesh["primitives"]) {
                const auto& attributes = primitive["attributes"];
                if (glb.root["materials"][primitive["material"].get<size_t>()]["name"] != "floor") continue;
                REQUIRE(attributes.contains("TEXCOORD_0"));
                CHECK(attributes.contains("TEXCOORD_1") == lightmaps);
                if (lightmaps) CHECK(attributes["TEXCOORD_0"] != attributes["TEXCOORD_1"]);
                const std::vector<float> positions = glb.floats(attributes["POSITION"].get<size_t>());
                const std::vector<float> uv0 = glb.floats(attributes["TEXCOORD_0"].get<size_t>());
                REQUIRE(uv0.size() / 2 == positions.size() / 3);
                for (size_t v = 0; v < uv0.size() / 2; ++v) {
                    const Vec2 xz(positions[3 * v], positions[3 * v + 2]);
                    bool found = false;
                    for (const auto& [where, uv] : expected)
                        if (glm::distance(where, xz) < 1e-6f) {
                            found = true;
                            CHECK(uv0[2 * v] == doctest::Approx(uv.x).epsilon(1e-6));
                            CHECK(uv0[2 * v + 1] == doctest::Approx(uv.y).epsilon(1e-6));
                        }
                    CHECK(found);
                    ++floor_vertices;
                }
            }
        CHECK(floor_vertices >= 6);
    }
}

TEST_CASE("textures: a missing map_Kd is one located warning, the material's colour, and a dependency") {
    const TempDir tmp;
    writeFloorScene(tmp.path, "missing.png");
    Diagnostics diagnostics;
    const Bake baked = bakeInMemory(tmp.path / "floor.obj", diagnostics);
    REQUIRE(baked.ok());
    CHECK(countMessages(diagnostics, Severity::Warning, "missing.png") == 1);
    const Diagnostic* warning = findMessage(diagnostics, "cannot read texture");
    REQUIRE(warning);
    CHECK(warning->location.file == (tmp.path / "floor.obj").string());
    for (const Mesh& mesh : baked.scene->meshes) CHECK(mesh.polygon_reflectance.empty());
    for (const Material& material : baked.scene->materials)
        if (material.name == "floor") CHECK(material.reflectance == Vec3(0.8f));

    const fs::path dep = tmp.path / "bake.d";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "floor.obj") + " -o " + quote(tmp.path / "out") +
                                     " --depfile " + quote(dep) + " --quality draft --no-lightmaps -q");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const std::string text = readBytes(dep);
    CHECK(text.substr(text.find(": ")).find((tmp.path / "missing.png").string()) != std::string::npos);
    // The glb names no texture it could not read.
    const Glb glb(readBytes(tmp.path / "out" / "floor.glb"));
    CHECK_FALSE(glb.root.contains("images"));
}

TEST_CASE("textures: VRML97 ImageTexture, RGB replaces diffuseColor and intensity modulates it; UVs by texCoordIndex") {
    const TempDir tmp;
    writePng(tmp.path / "rgb.png", 1, 1, 3, {188, 128, 64});
    writePng(tmp.path / "grey.png", 1, 1, 1, {188});
    writePng(tmp.path / "cutout.png", 2, 1, 2, {255, 255, 255, 0});  // grey + alpha: right texel cut out
    const std::string quad = "geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 1 0 1, 0 0 1 ] }"
                             " coordIndex [ 0 3 2 1 -1 ] texCoord TextureCoordinate { point [ 0 0, 1 0, 1 1, 0 1 ] }"
                             " texCoordIndex [ 3 2 1 0 -1 ] }";
    writeText(tmp.path / "scene.wrl",
              "#VRML V2.0 utf8\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0.2 0.4 0.6 }\n"
              "  texture ImageTexture { url \"rgb.png\" } } " + quad + " }\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0.2 0.4 0.6 }\n"
              "  texture ImageTexture { url \"grey.png\" } } " + quad + " }\n"
              "Shape { appearance Appearance { material DEF Leaves Material { diffuseColor 0.5 0.5 0.5 }\n"
              "  texture ImageTexture { url \"cutout.png\" } } " + quad + " }\n"
              "Shape { appearance Appearance { material USE Leaves texture ImageTexture { url \"cutout.png\" } } " + quad + " }\n"
              "Shape { appearance Appearance { material Material { diffuseColor 0.3 0.3 0.3 }\n"
              "  texture ImageTexture { url \"nowhere.png\" } } " + quad + " }\n");
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene((tmp.path / "scene.wrl").string(), {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->meshes.size() == 5);
    const double red = srgbDecoded(188), green = srgbDecoded(128), blue = srgbDecoded(64);
    auto rho = [&](size_t m) { return scene->meshes[m].polygon_reflectance.at(0); };
    CHECK(rho(0).x == doctest::Approx(red).epsilon(1e-6));  // replaced: the texture alone
    CHECK(rho(0).y == doctest::Approx(green).epsilon(1e-6));
    CHECK(rho(0).z == doctest::Approx(blue).epsilon(1e-6));
    CHECK(rho(1).x == doctest::Approx(0.2 * red).epsilon(1e-6));  // modulated by the intensity
    CHECK(rho(1).y == doctest::Approx(0.4 * red).epsilon(1e-6));
    CHECK(rho(1).z == doctest::Approx(0.6 * red).epsilon(1e-6));
    CHECK(rho(2).x == doctest::Approx(0.5).epsilon(1e-6));  // intensity 1 (the alpha is not colour)
    // texCoordIndex gives each corner its point: corner k of the face (coordinate 0 3 2 1) has UV 3 2 1 0.
    const Mesh& first = scene->meshes[0];
    REQUIRE(first.uv0.size() == first.positions.size());
    const std::vector<std::pair<Vec3, Vec2>> corners = {{{0, 0, 0}, {0, 1}}, {{0, 0, 1}, {1, 1}},
                                                        {{1, 0, 1}, {1, 0}}, {{1, 0, 0}, {0, 0}}};
    for (size_t v = 0; v < first.positions.size(); ++v)
        for (const auto& [p, uv] : corners)
            if (first.positions[v] == p) CHECK(first.uv0[v] == uv);
    // Cut-outs: one warning for the material, whichever meshes use it; the missing texture:
    // one warning at its ImageTexture, the material's own colour, a dependency.
    CHECK(countMessages(diagnostics, Severity::Warning, "alpha cutouts are baked as opaque") == 1);
    CHECK(countMessages(diagnostics, Severity::Warning, "nowhere.png") == 1);
    const Diagnostic* missing = findMessage(diagnostics, "nowhere.png");
    REQUIRE(missing);
    CHECK(missing->location.line == 10);
    CHECK(scene->meshes[4].polygon_reflectance.empty());
    CHECK(std::find(scene->input_files.begin(), scene->input_files.end(),
                    (tmp.path / "nowhere.png").lexically_normal().string()) != scene->input_files.end());
}

TEST_CASE("textures: VRML 1.0 Texture2 modulates the diffuse colour through textureCoordIndex") {
    const TempDir tmp;
    writePng(tmp.path / "half.png", 2, 1, 3, {0, 0, 0, 255, 255, 255});
    writeText(tmp.path / "scene.wrl",
              "#VRML V1.0 ascii\n"
              "Separator {\n"
              "  Material { diffuseColor 0.5 0.25 1 }\n"
              "  Texture2 { filename \"half.png\" }\n"
              "  Coordinate3 { point [ 0 0 0, 1 0 0, 1 0 1, 0 0 1, 2 0 0, 2 0 1 ] }\n"
              "  TextureCoordinate2 { point [ 0 0, 0.5 0, 0.5 1, 0 1, 1 0, 1 1 ] }\n"
              "  IndexedFaceSet { coordIndex [ 0 3 2 1 -1, 1 2 5 4 -1 ] textureCoordIndex [ 0 3 2 1 -1, 1 2 5 4 -1 ] }\n"
              "}\n");
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene((tmp.path / "scene.wrl").string(), {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->meshes.size() == 1);
    const Mesh& mesh = scene->meshes[0];
    REQUIRE(mesh.uv0.size() == mesh.positions.size());
    REQUIRE(mesh.polygon_reflectance.size() == 2);
    CHECK(mesh.polygon_reflectance[0] == Vec3(0.0f));                // black half
    CHECK(mesh.polygon_reflectance[1] == Vec3(0.5f, 0.25f, 0.999f));  // white half times the colour, clamped below 1
    CHECK(countMessages(diagnostics, Severity::Warning, "textured reflectance") == 1);
}

TEST_CASE("textures: map_Ke times Ke is each polygon's emission") {
    const TempDir tmp;
    writePng(tmp.path / "glow.png", 2, 1, 3, {255, 255, 255, 0, 0, 0});
    writeText(tmp.path / "floor.mtl", "newmtl light\nKd 0 0 0\nKe 2 2 2\nnewmtl floor\nKd 0.5 0.5 0.5\nKe 3 3 3\nmap_Ke glow.png\n");
    writeText(tmp.path / "floor.obj", "mtllib floor.mtl\n"
                                      "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 2 0 1\nv 1 0 1\nv 0 0 1\n"
                                      "vt 0 0\nvt 0.5 0\nvt 1 0\nvt 1 1\nvt 0.5 1\nvt 0 1\n"
                                      "usemtl floor\nf 1/1 6/6 5/5 2/2\nf 2/2 5/5 4/4 3/3\n");
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene((tmp.path / "floor.obj").string(), {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->meshes.size() == 1);
    REQUIRE(scene->meshes[0].polygon_emission.size() == 2);
    CHECK(scene->meshes[0].polygon_emission[0] == Vec3(3.0f));  // white half
    CHECK(scene->meshes[0].polygon_emission[1] == Vec3(0.0f));  // black half
    CHECK(scene->meshes[0].polygon_reflectance.empty());
}

TEST_CASE("textures: a normal map is embedded with per-vertex tangents along +u; a PPM is re-encoded to PNG") {
    const TempDir tmp;
    writePng(tmp.path / "half.png", 2, 1, 3, {0, 0, 0, 255, 255, 255});
    writePng(tmp.path / "flat.png", 1, 1, 3, {128, 128, 255});
    writeText(tmp.path / "glow.ppm", std::string("P6\n1 1\n255\n") + "\xff\x80\x40");
    writeFloorScene(tmp.path, "half.png", "norm flat.png\nKe 1 1 1\nmap_Ke glow.ppm\n");
    const fs::path out = tmp.path / "out";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "floor.obj") + " -o " + quote(out) + " --quality draft -q");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const Glb glb(readBytes(out / "floor.glb"));
    const nlohmann::json* floor_material = nullptr;
    size_t floor_index = 0;
    for (size_t i = 0; i < glb.root["materials"].size(); ++i)
        if (glb.root["materials"][i]["name"] == "floor") {
            floor_material = &glb.root["materials"][i];
            floor_index = i;
        }
    REQUIRE(floor_material);
    const auto imageOf = [&](const nlohmann::json& info) {
        return glb.root["images"][glb.root["textures"][info["index"].get<size_t>()]["source"].get<size_t>()];
    };
    const nlohmann::json normal_image = imageOf((*floor_material)["normalTexture"]);
    CHECK(glb.viewBytes(normal_image["bufferView"].get<size_t>()) == readBytes(tmp.path / "flat.png"));
    // The PPM becomes a PNG of the same pixel (no colour conversion on the way).
    const nlohmann::json emissive_image = imageOf((*floor_material)["emissiveTexture"]);
    CHECK(emissive_image["mimeType"] == "image/png");
    const std::string png = glb.viewBytes(emissive_image["bufferView"].get<size_t>());
    int width = 0, height = 0, channels = 0;
    unsigned char* pixels = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                                                  static_cast<int>(png.size()), &width, &height, &channels, 3);
    REQUIRE(pixels);
    CHECK(width == 1);
    CHECK(height == 1);
    CHECK(std::vector<int>(pixels, pixels + 3) == std::vector<int>{0xff, 0x80, 0x40});
    stbi_image_free(pixels);

    size_t checked = 0;
    for (const auto& mesh : glb.root["meshes"])
        for (const auto& primitive : mesh["primitives"]) {
            if (primitive["material"].get<size_t>() != floor_index) {
                CHECK_FALSE(primitive["attributes"].contains("TANGENT"));  // the lamp has no normal map
                continue;
            }
            REQUIRE(primitive["attributes"].contains("TANGENT"));
            const nlohmann::json& accessor = glb.root["accessors"][primitive["attributes"]["TANGENT"].get<size_t>()];
            CHECK(accessor["type"] == "VEC4");
            // u grows along +x; glTF's v (down the image) along -z, so the bitangent
            // cross(+y, +x) = -z keeps w = +1.
            const std::string bytes = glb.viewBytes(accessor["bufferView"].get<size_t>());
            std::vector<float> values(accessor["count"].get<size_t>() * 4);
            REQUIRE(bytes.size() >= values.size() * 4);
            std::memcpy(values.data(), bytes.data(), values.size() * 4);
            for (size_t v = 0; v < values.size() / 4; ++v) {
                CHECK(values[4 * v] == doctest::Approx(1.0).epsilon(1e-6));
                CHECK(values[4 * v + 1] == doctest::Approx(0.0).epsilon(1e-6));
                CHECK(values[4 * v + 2] == doctest::Approx(0.0).epsilon(1e-6));
                CHECK(values[4 * v + 3] == 1.0f);
                ++checked;
            }
        }
    CHECK(checked >= 6);
}

TEST_CASE("textures: a glb's embedded texture is read from the glb: radbake's own output baked again") {
    const TempDir tmp;
    writePng(tmp.path / "half.png", 2, 1, 3, {0, 0, 0, 255, 255, 255});
    writeFloorScene(tmp.path, "half.png");
    const RunResult run = runRadbake("bake " + quote(tmp.path / "floor.obj") + " -o " + quote(tmp.path / "out") +
                                     " --quality draft --no-lightmaps -q");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const std::string glb = (tmp.path / "out" / "floor.glb").string();
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene(glb, {}, diagnostics);
    REQUIRE(scene);
    CHECK(countMessages(diagnostics, Severity::Warning, "texture") == 0);
    const Mesh* floor = nullptr;
    for (const Mesh& mesh : scene->meshes)
        if (scene->materials[mesh.material].name == "floor") floor = &mesh;
    REQUIRE(floor);
    const TextureRef& texture = scene->materials[floor->material].base_color_texture;
    REQUIRE(texture.embedded);
    CHECK(*texture.embedded == readBytes(tmp.path / "half.png"));
    // glTF's v-down UVs come back v up, so the same halves: black times 0.8 and white times 0.8
    // (each quad is two triangles in a glb, so two polygons).
    REQUIRE(floor->polygon_reflectance.size() == 4);
    std::vector<float> red;
    for (const Vec3& rho : floor->polygon_reflectance) red.push_back(rho.x);
    std::sort(red.begin(), red.end());
    CHECK(red == std::vector<float>{0.0f, 0.0f, 0.8f, 0.8f});
    // The texture is inside the glb: no other input.
    CHECK(scene->input_files == std::vector<std::string>{fs::path(glb).lexically_normal().string()});
}

TEST_CASE("textures: VRML97 default texture coordinates: a face set's bounding box, an ElevationGrid's grid") {
    const TempDir tmp;
    writePng(tmp.path / "half.png", 2, 1, 3, {0, 0, 0, 128, 128, 128});  // left black, right sRGB 128
    writeText(tmp.path / "scene.wrl",
              "#VRML V2.0 utf8\n"
              "Shape { appearance Appearance { texture ImageTexture { url \"half.png\" } }\n"
              "  geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 2 0 0, 2 0 1, 1 0 1, 0 0 1 ] }\n"
              "    coordIndex [ 0 5 4 1 -1, 1 4 3 2 -1 ] } }\n"
              "Shape { appearance Appearance { texture ImageTexture { url \"half.png\" } }\n"
              "  geometry ElevationGrid { xDimension 3 zDimension 2 height [ 0 0 0, 0 0 0 ] } }\n"
              "Shape { appearance Appearance { texture ImageTexture { url \"half.png\" } }\n"
              "  geometry ElevationGrid { xDimension 3 zDimension 2 height [ 0 0 0, 0 0 0 ]\n"
              "    texCoord TextureCoordinate { point [ 1 0, 0.5 0, 0 0, 1 1, 0.5 1, 0 1 ] } } }\n");
    Diagnostics diagnostics;
    const std::optional<Scene> scene = importScene((tmp.path / "scene.wrl").string(), {}, diagnostics);
    REQUIRE(scene);
    REQUIRE(scene->meshes.size() == 3);
    const float grey = static_cast<float>(srgbDecoded(128));
    // The face set: s = x / 2 (x is the longest side), t = z / 2.
    const Mesh& faces = scene->meshes[0];
    REQUIRE(faces.uv0.size() == faces.positions.size());
    for (size_t v = 0; v < faces.positions.size(); ++v)
        CHECK(faces.uv0[v] == Vec2(faces.positions[v].x / 2.0f, faces.positions[v].z / 2.0f));
    REQUIRE(faces.polygon_reflectance.size() == 2);
    CHECK(faces.polygon_reflectance[0] == Vec3(0.0f));
    CHECK(faces.polygon_reflectance[1].x == doctest::Approx(grey).epsilon(1e-6));
    // The grid: s = i / 2, t = j; then the given coordinates, mirrored in s.
    REQUIRE(scene->meshes[1].polygon_reflectance.size() == 2);
    CHECK(scene->meshes[1].polygon_reflectance[0] == Vec3(0.0f));
    CHECK(scene->meshes[1].polygon_reflectance[1].x == doctest::Approx(grey).epsilon(1e-6));
    REQUIRE(scene->meshes[2].polygon_reflectance.size() == 2);
    CHECK(scene->meshes[2].polygon_reflectance[0].x == doctest::Approx(grey).epsilon(1e-6));
    CHECK(scene->meshes[2].polygon_reflectance[1] == Vec3(0.0f));
}

TEST_CASE("textures: a texture swapped for a link out of the tree after the import is not embedded in the glb") {
    const TempDir tmp;
    fs::create_directories(tmp.path / "scene");
    fs::create_directories(tmp.path / "secret");
    writePng(tmp.path / "scene" / "half.png", 2, 1, 3, {0, 0, 0, 255, 255, 255});
    writePng(tmp.path / "secret" / "key.png", 1, 1, 3, {12, 34, 56});
    writeFloorScene(tmp.path / "scene", "half.png");
    Diagnostics diagnostics;
    const Bake result = bakeInMemory(tmp.path / "scene" / "floor.obj", diagnostics);
    REQUIRE(result.ok());
    // Between the import, which checked the texture, and the writer, which reads it again.
    fs::remove(tmp.path / "scene" / "half.png");
    fs::create_symlink(tmp.path / "secret" / "key.png", tmp.path / "scene" / "half.png");
    REQUIRE(writeBake(result, tmp.path / "out", diagnostics));
    const Glb glb(readBytes(tmp.path / "out" / "floor.glb"));
    CHECK(glb.bin.find(readBytes(tmp.path / "secret" / "key.png")) == std::string::npos);
    for (const auto& material : glb.root["materials"])
        CHECK_FALSE(material["pbrMetallicRoughness"].contains("baseColorTexture"));
}

TEST_CASE("textures: VRML primitives keep their texture in the glb, through the standard's coordinates") {
    const TempDir tmp;
    writePng(tmp.path / "half.png", 2, 1, 3, {0, 0, 0, 255, 255, 255});
    std::ofstream(tmp.path / "shapes.wrl") << "#VRML V2.0 utf8\n"
        "PointLight { location 0 4 4 }\n"
        "DEF T Appearance { texture ImageTexture { url \"half.png\" } }\n"
        "Transform { translation -3 0 0 children Shape { appearance USE T geometry Box { } } }\n"
        "Transform { translation -1 0 0 children Shape { appearance USE T geometry Sphere { } } }\n"
        "Transform { translation 1 0 0 children Shape { appearance USE T geometry Cylinder { } } }\n"
        "Transform { translation 3 0 0 children Shape { appearance USE T geometry Cone { } } }\n";
    const fs::path out = tmp.path / "out";
    const RunResult run = runRadbake("bake " + quote(tmp.path / "shapes.wrl") + " -o " + quote(out) + " --quality draft -q");
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const Glb glb(readBytes(out / "shapes.glb"));
    size_t primitives = 0;
    for (const auto& mesh : glb.root["meshes"])
        for (const auto& primitive : mesh["primitives"]) {
            const nlohmann::json& material = glb.root["materials"][primitive["material"].get<size_t>()];
            REQUIRE(material["pbrMetallicRoughness"].contains("baseColorTexture"));
            CHECK(primitive["attributes"].contains("TEXCOORD_0"));
            CHECK(primitive["attributes"]["TEXCOORD_0"] != primitive["attributes"]["TEXCOORD_1"]);
            ++primitives;
        }
    CHECK(primitives >= 4);
    REQUIRE(glb.root["images"].size() == 2);  // the texture and the lightmap
}

TEST_CASE("--lightmap-quantity radiance: each texel the irradiance times the reflectance of its polygon, named as such") {
    const TempDir tmp;
    writePng(tmp.path / "half.png", 2, 1, 3, {0, 0, 0, 255, 255, 255});  // the floor's polygons: rho 0 and 0.8
    writeFloorScene(tmp.path, "half.png");
    const std::string bake = "bake " + quote(tmp.path / "floor.obj") + " --quality draft -q --texel-density 32 --solution " +
                             quote(tmp.path / "floor.sol");
    const RunResult irradiance = runRadbake(bake + " -o " + quote(tmp.path / "irradiance"));
    const RunResult radiance = runRadbake(bake + " -o " + quote(tmp.path / "radiance") + " --lightmap-quantity radiance");
    INFO(irradiance.output, radiance.output);
    REQUIRE(irradiance.exit_code == 0);
    REQUIRE(radiance.exit_code == 0);
    Diagnostics diagnostics;
    const std::optional<RgbImage> h = readExr(tmp.path / "irradiance" / "lightmaps" / "floor_0.exr", diagnostics);
    const std::optional<RgbImage> l = readExr(tmp.path / "radiance" / "lightmaps" / "floor_0.exr", diagnostics);
    REQUIRE(h);
    REQUIRE(l);
    REQUIRE(h->rgb.size() == l->rgb.size());
    size_t black = 0, white = 0;
    for (size_t i = 0; i < h->rgb.size(); ++i) {
        if (!(h->rgb[i] > 1e-3f)) continue;
        const float ratio = l->rgb[i] / h->rgb[i];
        CAPTURE(i);
        CAPTURE(ratio);
        CHECK((ratio == 0.0f || std::fabs(ratio - 0.8f) < 2e-3f));  // half floats: 11 bits
        black += ratio == 0.0f;
        white += ratio > 0.0f;
    }
    CHECK(black > 20);  // the floor's black half (and the lamp, Kd 0)
    CHECK(white > 20);  // its white half
    const auto quantityOf = [](const RgbImage& image) {
        for (const auto& [name, value] : image.attributes)
            if (name == "radbake:quantity") return value;
        return std::string();
    };
    CHECK(quantityOf(*h).starts_with("H/pi"));
    CHECK(quantityOf(*l).starts_with("rho H/pi"));
    for (const char* kind : {"irradiance", "radiance"}) {
        const Glb glb(readBytes(tmp.path / kind / "floor.glb"));
        for (const auto& material : glb.root["materials"])
            if (material.contains("extensions")) CHECK(material["extras"]["radbake_lightmap_quantity"] == kind);
    }
}
