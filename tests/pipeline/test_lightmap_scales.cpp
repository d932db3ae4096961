// --lightmap-scales: the side file's rules (located errors), their resolution to meshes by
// mesh name, then material name, and the bake's texel counts following them within the budget.
#include <doctest/doctest.h>

#include "radbake.h"

using namespace radbake;

namespace {

// Three 1 m x 1 m floors 'a', 'b', 'c'; a and b of material 'stone', c of 'wood'; a lamp above.
Scene floorsScene() {
    Scene scene;
    scene.name = "floors";
    Material stone, wood, lamp;
    stone.name = "stone";
    stone.reflectance = Vec3(0.5f);
    wood.name = "wood";
    wood.reflectance = Vec3(0.5f);
    lamp.name = "lamp";
    lamp.reflectance = Vec3(0.0f);
    lamp.emission = Vec3(1.0f);
    scene.materials = {stone, wood, lamp};
    const auto quad = [](const std::string& name, float x0, float y, uint32_t material, bool down) {
        Mesh mesh;
        mesh.name = name;
        mesh.positions = {{x0, y, 0}, {x0, y, 1}, {x0 + 1, y, 1}, {x0 + 1, y, 0}};
        mesh.triangles = down ? std::vector<UVec3>{{0, 2, 1}, {0, 3, 2}} : std::vector<UVec3>{{0, 1, 2}, {0, 2, 3}};
        mesh.triangle_polygon = {0, 0};
        mesh.polygon_count = 1;
        mesh.material = material;
        return mesh;
    };
    scene.meshes = {quad("a", 0, 0, 0, false), quad("b", 2, 0, 0, false), quad("c", 4, 0, 1, false),
                    quad("lamp", 2, 2, 2, true)};
    return scene;
}

}  // namespace

TEST_CASE("lightmap scale file: rules, comments, and located errors") {
    Diagnostics diagnostics;
    const auto rules = parseLightmapScales("# name scale\n\nFloor 0.5\n  Gold frame   4  # trailing comment\n",
                                           "scales.txt", diagnostics);
    REQUIRE(rules);
    REQUIRE(rules->size() == 2);
    CHECK((*rules)[0].name == "Floor");
    CHECK((*rules)[0].scale == 0.5);
    CHECK((*rules)[0].location.line == 3);
    CHECK((*rules)[1].name == "Gold frame");  // the name is everything before the last word
    CHECK((*rules)[1].scale == 4.0);
    CHECK(diagnostics.all().empty());

    const std::vector<std::pair<std::string, int>> bad = {
        {"Floor\n", 1}, {"Floor -1\n", 1}, {"Floor 0\n", 1}, {"Floor two\n", 1}, {"# x\nFloor inf\n", 2},
        {"a 1\nb 2\na 3\n", 3}};
    for (const auto& [text, line] : bad) {
        CAPTURE(text);
        Diagnostics d;
        CHECK_FALSE(parseLightmapScales(text, "scales.txt", d));
        REQUIRE(d.errorCount() == 1);
        CHECK(d.all()[0].location.file == "scales.txt");
        CHECK(d.all()[0].location.line == line);
    }
    CHECK_FALSE(readLightmapScales("/nonexistent/scales.txt", diagnostics));
    const int errors = diagnostics.errorCount();
    CHECK_FALSE(readLightmapScales("/tmp", diagnostics));  // a folder is no scale file
    CHECK(diagnostics.errorCount() == errors + 1);
}

TEST_CASE("lightmap scales resolve by mesh name first, then material name; unknown names warn") {
    const Scene scene = floorsScene();
    Diagnostics diagnostics;
    const auto rules = parseLightmapScales("stone 2\nb 0.5\nmissing 3\n", "scales.txt", diagnostics);
    REQUIRE(rules);
    const std::vector<double> scales = meshTexelScales(scene, *rules, diagnostics);
    CHECK(scales == std::vector<double>{2.0, 0.5, 1.0, 1.0});  // a by material, b by name, c and the lamp unscaled
    REQUIRE(diagnostics.warningCount() == 1);
    CHECK(diagnostics.all()[0].location.line == 3);
}

TEST_CASE("a bake with lightmap scales: texel counts follow the scales, within the budget") {
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.lightmaps.texels_per_unit = 16.0;
    Diagnostics diagnostics;
    options.lightmaps.scales = *parseLightmapScales("a 2\nc 0.5\n", "scales.txt", diagnostics);
    Progress progress(false);
    const auto texelsPerMesh = [](const Bake& bake) {
        std::vector<double> texels(bake.scene->meshes.size(), 0.0);
        for (const LightmapChart& chart : bake.lightmaps->lightmaps.layout.charts)
            texels[chart.mesh] += static_cast<double>(chart.width) * chart.height;
        return texels;
    };
    const Bake scaled = bake(floorsScene(), options, progress, diagnostics);
    REQUIRE(scaled.ok());
    CHECK(texelsPerMesh(scaled) == std::vector<double>{1024.0, 256.0, 64.0, 256.0});

    // Over the budget, the density drops for every mesh alike: the ratios stay.
    options.lightmaps.texels_per_unit = 0.0;  // the default density, lowered with a warning
    options.lightmaps.max_texels = 800;
    const Bake tight = bake(floorsScene(), options, progress, diagnostics);
    REQUIRE(tight.ok());
    const std::vector<double> texels = texelsPerMesh(tight);
    CHECK(texels[0] + texels[1] + texels[2] + texels[3] <= 800.0);
    CHECK(texels[0] / texels[1] == doctest::Approx(4.0).epsilon(0.3));  // integer texel sides round
    CHECK(texels[1] / texels[2] == doctest::Approx(4.0).epsilon(0.3));
}

TEST_CASE("lightmap scales in a bake without lightmaps are a warning, not silently nothing") {
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.lightmaps.enabled = false;
    Diagnostics diagnostics;
    options.lightmaps.scales = *parseLightmapScales("a 2\n", "scales.txt", diagnostics);
    Progress progress(false);
    const Bake result = bake(floorsScene(), options, progress, diagnostics);
    REQUIRE(result.ok());
    REQUIRE(diagnostics.warningCount() == 1);
    CHECK(diagnostics.all()[0].message == "lightmap scales have no effect: the bake has no lightmaps");
    CHECK(diagnostics.all()[0].location.file == "scales.txt");
}
