// Lightmap meshes: the same surface as the source (area, facing), split only at chart
// seams, and every UV inside its chart's texel rectangle in [0, 1].
#include <doctest/doctest.h>

#include "bake/lightmap_mesh.h"
#include "bake/lightmap_pack.h"

using namespace radbake;

namespace {

double meshArea(const std::vector<Vec3>& positions, const std::vector<UVec3>& triangles, DVec3* normal_sum) {
    double area = 0.0;
    for (const UVec3& t : triangles) {
        const DVec3 c = glm::cross(DVec3(positions[t.y]) - DVec3(positions[t.x]), DVec3(positions[t.z]) - DVec3(positions[t.x]));
        area += 0.5 * glm::length(c);
        if (normal_sum) *normal_sum += 0.5 * c;
    }
    return area;
}

Mesh boxWithoutBottom(float s) {
    Mesh mesh;
    const auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
        const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
        mesh.triangles.push_back({base, base + 1, base + 2});
        mesh.triangles.push_back({base, base + 2, base + 3});
        mesh.triangle_polygon.push_back(mesh.polygon_count);
        mesh.triangle_polygon.push_back(mesh.polygon_count++);
    };
    quad({0, s, 0}, {0, s, s}, {s, s, s}, {s, s, 0});  // top, +Y
    quad({0, 0, 0}, {0, s, 0}, {s, s, 0}, {s, 0, 0});  // -Z
    quad({0, 0, s}, {s, 0, s}, {s, s, s}, {0, s, s});  // +Z
    return mesh;
}

}  // namespace

TEST_CASE("lightmap meshes keep the surface and put every UV inside its chart") {
    Scene scene;
    scene.materials.resize(1);
    scene.meshes = {boxWithoutBottom(3.0f)};
    LightmapOptions options;
    options.texels_per_metre = 16.0;  // 48 texels a side
    options.max_chart_texels = 20; // the cap cuts every face into 3 x 3 pieces
    options.atlas_size = 256;
    LightmapLayout layout;
    Diagnostics diagnostics;
    REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
    CHECK(layout.charts.size() == 27);
    const std::vector<LightmapMesh> meshes = lightmapMeshes(scene, layout);
    REQUIRE(meshes.size() == 1);
    const LightmapMesh& mesh = meshes[0];
    DVec3 source_normal(0.0), normal(0.0);
    CHECK(meshArea(mesh.positions, mesh.triangles, &normal) ==
          doctest::Approx(meshArea(scene.meshes[0].positions, scene.meshes[0].triangles, &source_normal)));
    CHECK(glm::length(normal - source_normal) < 1e-4);  // same facing, piece by piece summed
    CHECK(mesh.source_triangle.size() == mesh.triangles.size());
    // Per chart (in order), its vertices' UVs lie in its texel rectangle.
    for (size_t v = 0; v < mesh.uv.size(); ++v) {
        CHECK(mesh.uv[v].x >= 0.0f);
        CHECK(mesh.uv[v].y >= 0.0f);
        CHECK(mesh.uv[v].x <= 1.0f);
        CHECK(mesh.uv[v].y <= 1.0f);
    }
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3 tri = mesh.triangles[t];
        bool inside_some_chart = false;
        for (const LightmapChart& chart : layout.charts) {
            const LightmapAtlas& atlas = layout.atlases[chart.atlas];
            bool inside = chart.atlas == mesh.atlas[tri.x];
            for (int k = 0; k < 3; ++k) {
                const Vec2 uv = mesh.uv[tri[k]];
                const double x = uv.x * atlas.width, y = uv.y * atlas.height;
                inside = inside && x >= chart.x - 1e-3 && x <= chart.x + chart.width + 1e-3 && y >= chart.y - 1e-3 &&
                         y <= chart.y + chart.height + 1e-3;
            }
            inside_some_chart = inside_some_chart || inside;
        }
        CHECK(inside_some_chart);
    }
    // Pieces of a 3 x 3 cut share vertices only within a piece: 9 pieces of a quad have
    // 4 corners each when the cut misses the diagonal's ends, more where it crosses it.
    CHECK(mesh.positions.size() > 27 * 4);
}

TEST_CASE("lightmap vertices carry source attributes: positions interpolate back to themselves") {
    Scene scene;
    scene.materials.resize(1);
    scene.meshes = {boxWithoutBottom(2.0f)};
    LightmapOptions options;
    options.texels_per_metre = 10.0;
    options.max_chart_texels = 7;  // cuts make vertices in the middle of source triangles
    options.atlas_size = 128;
    LightmapLayout layout;
    Diagnostics diagnostics;
    REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
    const LightmapMesh mesh = lightmapMeshes(scene, layout)[0];
    REQUIRE(mesh.source_corners.size() == mesh.positions.size());
    REQUIRE(mesh.barycentric.size() == mesh.positions.size());
    CHECK(mesh.positions.size() > scene.meshes[0].positions.size());
    const std::vector<Vec3>& source = scene.meshes[0].positions;
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3 w = mesh.barycentric[v];
        CHECK(w.x >= 0.0f);
        CHECK(w.y >= 0.0f);
        CHECK(w.z >= 0.0f);
        CHECK(w.x + w.y + w.z == doctest::Approx(1.0).epsilon(1e-6));
        CHECK(glm::length(interpolateSource(mesh, v, source) - mesh.positions[v]) < 1e-5f);
    }
}

TEST_CASE("a chart bent across smooth edges keeps its vertices on their own faces") {
    // An open half-cylinder of 8 facets (22.5 degrees apart) with crease angle 0.5 rad.
    Mesh half;
    half.crease_angle = 0.5f;
    for (int i = 0; i <= 8; ++i) {
        const double theta = kPi * i / 8;
        half.positions.push_back(Vec3(std::cos(theta), 0.0, std::sin(theta)));
        half.positions.push_back(Vec3(std::cos(theta), 1.5, std::sin(theta)));
    }
    for (uint32_t i = 0; i < 8; ++i) {
        const uint32_t b0 = 2 * i, t0 = b0 + 1, b1 = b0 + 2, t1 = b0 + 3;
        half.triangles.push_back({b0, t0, t1});
        half.triangles.push_back({b0, t1, b1});
        half.triangle_polygon.push_back(i);
        half.triangle_polygon.push_back(i);
    }
    half.polygon_count = 8;
    Scene scene;
    scene.materials.resize(1);
    scene.meshes = {half};
    LightmapOptions options;
    options.texels_per_metre = 12.0;
    options.max_chart_texels = 10;  // and cut by the cap: pieces of bent charts
    options.atlas_size = 256;
    LightmapLayout layout;
    Diagnostics diagnostics;
    REQUIRE(packLightmapCharts(buildLightmapCharts(scene, options), options, layout, diagnostics));
    size_t bent = 0;
    for (const LightmapChart& chart : layout.charts)
        for (const ChartFace& face : chart.faces) bent += glm::dot(face.normal_world, chart.normal_world) < 0.99;
    CHECK(bent > 0);
    const LightmapMesh mesh = lightmapMeshes(scene, layout)[0];
    CHECK(meshArea(mesh.positions, mesh.triangles, nullptr) ==
          doctest::Approx(meshArea(half.positions, half.triangles, nullptr)).epsilon(1e-6));
    for (size_t v = 0; v < mesh.positions.size(); ++v)
        CHECK(glm::length(interpolateSource(mesh, v, half.positions) - mesh.positions[v]) < 1e-5f);
    // Each lightmap triangle lies on its source triangle's plane.
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3 s = half.triangles[mesh.source_triangle[t]];
        const DVec3 a(half.positions[s.x]);
        const DVec3 n = glm::normalize(glm::cross(DVec3(half.positions[s.y]) - a, DVec3(half.positions[s.z]) - a));
        for (int k = 0; k < 3; ++k) CHECK(std::fabs(glm::dot(DVec3(mesh.positions[mesh.triangles[t][k]]) - a, n)) < 1e-5);
    }
}
