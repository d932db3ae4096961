// Lightmap charts: a cube gives 6 charts of its faces; coplanar pieces join only when
// connected; a floor larger than the cap is cut into pieces that keep its whole area;
// every face lies inside its chart's texel rectangle.
#include <doctest/doctest.h>

#include <cmath>
#include <set>

#include "bake/lightmap_charts.h"

using namespace radbake;

namespace {

// Adds a convex polygon (counter-clockwise from the front) as a fan of triangles.
void addQuad(Mesh& mesh, const std::vector<Vec3>& loop, bool share_vertices) {
    uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    std::vector<uint32_t> ids;
    for (const Vec3& p : loop) {
        uint32_t id = base++;
        if (share_vertices)
            for (uint32_t v = 0; v < mesh.positions.size(); ++v)
                if (mesh.positions[v] == p) id = v;
        if (id >= mesh.positions.size()) {
            id = static_cast<uint32_t>(mesh.positions.size());
            mesh.positions.push_back(p);
        }
        ids.push_back(id);
    }
    for (size_t k = 1; k + 1 < ids.size(); ++k) {
        mesh.triangles.push_back({ids[0], ids[k], ids[k + 1]});
        mesh.triangle_polygon.push_back(mesh.polygon_count);
    }
    ++mesh.polygon_count;
}

Mesh cubeMesh(float s, bool share_vertices) {
    Mesh mesh;
    mesh.name = "cube";
    const auto c = [s](int x, int y, int z) { return Vec3(x * s, y * s, z * s); };
    addQuad(mesh, {c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(1, 0, 0)}, share_vertices);  // -Z
    addQuad(mesh, {c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)}, share_vertices);  // +Z
    addQuad(mesh, {c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)}, share_vertices);  // -Y
    addQuad(mesh, {c(0, 1, 0), c(0, 1, 1), c(1, 1, 1), c(1, 1, 0)}, share_vertices);  // +Y
    addQuad(mesh, {c(0, 0, 0), c(0, 0, 1), c(0, 1, 1), c(0, 1, 0)}, share_vertices);  // -X
    addQuad(mesh, {c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1)}, share_vertices);  // +X
    return mesh;
}

Scene sceneOf(std::vector<Mesh> meshes) {
    Scene scene;
    scene.name = "test";
    scene.materials.resize(meshes.size());
    for (uint32_t m = 0; m < meshes.size(); ++m) meshes[m].material = m;
    scene.meshes = std::move(meshes);
    return scene;
}

// Every face point lies inside the chart's texel rectangle (to rounding).
void checkFacesInside(const LightmapChart& chart) {
    for (const ChartFace& face : chart.faces)
        for (const DVec2& p : face.p_plane) {
            const DVec2 t = (p - chart.min_plane) * chart.texels_per_metre;
            CHECK(t.x >= -1e-9);
            CHECK(t.y >= -1e-9);
            CHECK(t.x <= chart.width + 1e-6);
            CHECK(t.y <= chart.height + 1e-6);
        }
}

// Chart points map back onto the source triangle's plane in world space.
void checkFacesOnTriangles(const Scene& scene, const LightmapChart& chart) {
    const Mesh& mesh = scene.meshes[chart.mesh];
    for (const ChartFace& face : chart.faces) {
        const UVec3 tri = mesh.triangles[face.triangle];
        const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
        const DVec3 n = glm::normalize(glm::cross(b - a, c - a));
        CHECK(glm::dot(n, chart.normal_world) == doctest::Approx(1.0));
        for (const DVec2& p : face.p_plane) CHECK(std::fabs(glm::dot(chart.worldPoint(p) - a, n)) < 1e-5);
    }
}

}  // namespace

TEST_CASE("a cube gives 6 charts, one per face, with shared or split vertices") {
    for (bool share : {true, false}) {
        CAPTURE(share);
        const Scene scene = sceneOf({cubeMesh(2.0f, share)});
        CHECK(scene.meshes[0].positions.size() == (share ? 8u : 24u));
        LightmapOptions options;
        options.texels_per_metre = 10.0;
        const std::vector<LightmapChart> charts = buildLightmapCharts(scene, options);
        REQUIRE(charts.size() == 6);
        std::set<uint32_t> triangles;
        std::set<std::array<int, 3>> normals;
        for (const LightmapChart& chart : charts) {
            CHECK(chart.faces.size() == 2);
            CHECK(chart.area == doctest::Approx(4.0));
            CHECK(chart.width == 20);
            CHECK(chart.height == 20);
            for (const ChartFace& face : chart.faces) triangles.insert(face.triangle);
            normals.insert({static_cast<int>(std::lround(chart.normal_world.x)), static_cast<int>(std::lround(chart.normal_world.y)),
                            static_cast<int>(std::lround(chart.normal_world.z))});
            checkFacesInside(chart);
            checkFacesOnTriangles(scene, chart);
        }
        CHECK(triangles.size() == 12);
        CHECK(normals.size() == 6);
    }
}

TEST_CASE("coplanar polygons join only when connected; tiny and degenerate ones") {
    Mesh mesh;
    // An L of three unit squares on z = 0 (connected), and a separate square at x = 5.
    addQuad(mesh, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, true);
    addQuad(mesh, {{1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}}, true);
    addQuad(mesh, {{0, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}}, true);
    addQuad(mesh, {{5, 0, 0}, {6, 0, 0}, {6, 1, 0}, {5, 1, 0}}, true);
    // A 1 cm triangle and a degenerate one (three collinear points).
    addQuad(mesh, {{8, 0, 0}, {8.01f, 0, 0}, {8, 0.01f, 0}}, true);
    addQuad(mesh, {{9, 0, 0}, {9.5f, 0, 0}, {10, 0, 0}}, true);
    const Scene scene = sceneOf({mesh});
    LightmapOptions options;
    options.texels_per_metre = 8.0;
    options.min_chart_texels = 3;
    const std::vector<LightmapChart> charts = buildLightmapCharts(scene, options);
    REQUIRE(charts.size() == 3);
    CHECK(charts[0].faces.size() == 6);
    CHECK(charts[0].area == doctest::Approx(3.0));
    CHECK(charts[0].width == 16);
    CHECK(charts[0].height == 16);
    CHECK(charts[1].faces.size() == 2);
    CHECK(charts[1].width == 8);
    CHECK(charts[2].faces.size() == 1);
    CHECK(charts[2].width == 3);  // the minimum
    CHECK(charts[2].height == 3);
    CHECK(charts[2].area == doctest::Approx(0.5e-4).epsilon(1e-3));
    for (const LightmapChart& chart : charts) checkFacesInside(chart);
}

TEST_CASE("a floor larger than the cap is split into cap-sized pieces that keep its area") {
    Mesh floor;
    addQuad(floor, {{0, 0, 0}, {0, 0, 4}, {10, 0, 4}, {10, 0, 0}}, true);  // 10 x 4 m, facing +Y
    const Scene scene = sceneOf({floor});
    LightmapOptions options;
    options.texels_per_metre = 16.0;  // 160 x 64 texels
    options.max_chart_texels = 48;
    const std::vector<LightmapChart> charts = buildLightmapCharts(scene, options);
    // ceil(160 / 48) = 4 columns by ceil(64 / 48) = 2 rows; the floor's axes are world X and Z.
    REQUIRE(charts.size() == 8);
    double area = 0.0;
    std::multiset<std::pair<int, int>> sizes;
    for (const LightmapChart& chart : charts) {
        CHECK(chart.width <= 48);
        CHECK(chart.height <= 48);
        area += chart.area;
        sizes.insert({std::max(chart.width, chart.height), std::min(chart.width, chart.height)});
        checkFacesInside(chart);
        checkFacesOnTriangles(scene, chart);
    }
    CHECK(area == doctest::Approx(40.0).epsilon(1e-9));
    // Pieces: 3 full columns of 48 and one of 16, by rows of 48 and 16 texels.
    CHECK(sizes == std::multiset<std::pair<int, int>>{{48, 48}, {48, 48}, {48, 48}, {48, 16}, {48, 16}, {48, 16}, {48, 16}, {16, 16}});

    options.max_chart_texels = 1000;
    const std::vector<LightmapChart> whole = buildLightmapCharts(scene, options);
    REQUIRE(whole.size() == 1);
    CHECK(std::max(whole[0].width, whole[0].height) == 160);
    CHECK(std::min(whole[0].width, whole[0].height) == 64);
}

TEST_CASE("the cap never exceeds what an atlas holds with padding") {
    Mesh floor;
    addQuad(floor, {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}}, true);
    LightmapOptions options;
    options.texels_per_metre = 32.0;  // 128 texels
    options.max_chart_texels = 1000;
    options.atlas_size = 64;
    options.padding = 2;  // at most 60 texels a side
    const std::vector<LightmapChart> charts = buildLightmapCharts(sceneOf({floor}), options);
    CHECK(charts.size() == 9);  // ceil(128 / 60) = 3 by 3
    for (const LightmapChart& chart : charts) CHECK(chart.width <= 60);
}

namespace {

// The side of a cylinder around +Y (radius 1, height 2) as `facets` outward quads with shared
// vertices, two triangles each.
Mesh cylinderSide(int facets, float crease_angle) {
    Mesh mesh;
    mesh.name = "cylinder";
    mesh.crease_angle = crease_angle;
    for (int i = 0; i < facets; ++i) {
        const double theta = 2.0 * kPi * i / facets;
        mesh.positions.push_back(Vec3(std::cos(theta), 0.0, std::sin(theta)));
        mesh.positions.push_back(Vec3(std::cos(theta), 2.0, std::sin(theta)));
    }
    for (uint32_t i = 0; i < static_cast<uint32_t>(facets); ++i) {
        const uint32_t b0 = 2 * i, t0 = b0 + 1, b1 = 2 * ((i + 1) % facets), t1 = b1 + 1;
        mesh.triangles.push_back({b0, t0, t1});
        mesh.triangles.push_back({b0, t1, b1});
        mesh.triangle_polygon.push_back(i);
        mesh.triangle_polygon.push_back(i);
    }
    mesh.polygon_count = static_cast<uint32_t>(facets);
    return mesh;
}

bool strictlyInside(const DVec2& p, const std::vector<DVec2>& polygon, double margin) {
    for (size_t k = 0; k < polygon.size(); ++k) {
        const DVec2 e = polygon[(k + 1) % polygon.size()] - polygon[k], d = p - polygon[k];
        if ((e.x * d.y - e.y * d.x) / glm::length(e) <= margin) return false;
    }
    return true;
}

}  // namespace

TEST_CASE("charts grow across smooth edges within the cone, without overlap or flips") {
    const double cone_cos = std::cos(35.0 * kPi / 180.0);
    const Scene scene = sceneOf({cylinderSide(32, 0.5f)});  // facets 11.25 degrees apart, crease 28.6
    const Mesh& mesh = scene.meshes[0];
    for (const UVec3& t : mesh.triangles) {  // the facets face outwards
        const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
        const DVec3 centre = (a + b + c) / 3.0;
        CHECK(glm::dot(glm::cross(b - a, c - a), DVec3(centre.x, 0.0, centre.z)) > 0.0);
    }
    LightmapOptions options;
    options.texels_per_metre = 16.0;
    const std::vector<LightmapChart> charts = buildLightmapCharts(scene, options);
    // 360 degrees of facets, at most 7 facets (+-3 around the seed) within a 35 degree cone.
    CHECK(charts.size() >= 5);
    CHECK(charts.size() <= 8);
    std::multiset<uint32_t> triangles;
    double area = 0.0;
    for (const LightmapChart& chart : charts) {
        CHECK(chart.faces.size() >= 2);  // greedy seeds in triangle order: 7 facets, then 4 each, one left over
        area += chart.area;
        for (const ChartFace& face : chart.faces) {
            triangles.insert(face.triangle);
            // Within the cone, facing the chart's normal (no flip), stretch at most 1 / cos(cone).
            const double cos_angle = glm::dot(face.normal_world, chart.normal_world);
            CHECK(cos_angle >= cone_cos);
            const double world_area =
                0.5 * glm::length(glm::cross(face.corner_world[1] - face.corner_world[0], face.corner_world[2] - face.corner_world[0]));
            const double plane_area = polygonArea(face.p_plane);
            CHECK(plane_area > 0.0);
            CHECK(world_area / plane_area <= 1.0 / cone_cos + 1e-9);
            // Plane points lift back onto the face's own triangle, corners onto its corners.
            const UVec3 tri = mesh.triangles[face.triangle];
            for (int k = 0; k < 3; ++k)
                CHECK(glm::length(face.worldPoint(face.corner_plane[k]) - DVec3(mesh.positions[tri[k]])) < 1e-6);
            for (const DVec2& p : face.p_plane)
                CHECK(std::fabs(glm::dot(face.worldPoint(p) - face.corner_world[0], face.normal_world)) < 1e-6);
        }
        checkFacesInside(chart);
        // No overlap, texel by texel: 4 x 4 points per texel, each inside at most one face.
        size_t covered_points = 0;
        for (int j = 0; j < chart.height; ++j)
            for (int i = 0; i < chart.width; ++i)
                for (int sj = 0; sj < 4; ++sj)
                    for (int si = 0; si < 4; ++si) {
                        const DVec2 p = chart.min_plane + (DVec2(i, j) + (DVec2(si, sj) + 0.5) / 4.0) / chart.texels_per_metre;
                        int inside = 0;
                        for (const ChartFace& face : chart.faces) inside += strictlyInside(p, face.p_plane, 1e-9);
                        CHECK(inside <= 1);
                        covered_points += inside == 1;
                    }
        CHECK(covered_points > 0);
    }
    CHECK(triangles.size() == 64);  // every triangle in exactly one chart
    CHECK(std::set<uint32_t>(triangles.begin(), triangles.end()).size() == 64);
    CHECK(area < 2.0 * 2.0 * kPi);  // projected: less than the side's surface
    CHECK(area > 2.0 * 2.0 * kPi * cone_cos);

    // Crease angle 0: every facet is its own flat chart, as before.
    const std::vector<LightmapChart> flat = buildLightmapCharts(sceneOf({cylinderSide(32, 0.0f)}), options);
    CHECK(flat.size() == 32);
    for (const LightmapChart& chart : flat) CHECK(chart.faces.size() == 2);
}

TEST_CASE("a cube with a large crease angle is still 6 charts") {
    for (bool share : {true, false}) {
        Mesh cube = cubeMesh(1.0f, share);
        cube.crease_angle = 1.2f;  // 69 degrees: its 90 degree edges are still creases
        LightmapOptions options;
        options.texels_per_metre = 10.0;
        CHECK(buildLightmapCharts(sceneOf({cube}), options).size() == 6);
        cube.crease_angle = 1.6f;  // above 90 degrees: the edges are smooth, but 90 > the 35 degree cone
        CHECK(buildLightmapCharts(sceneOf({cube}), options).size() == 6);
    }
}

TEST_CASE("per-mesh texel scale: a mesh at scale s gets s^2 times the texels, s times the density") {
    // Two 1 m x 1 m floors, 16 texels per metre: 16 x 16 texels each at scale 1.
    const auto floor = [](float x0) {
        Mesh mesh;
        addQuad(mesh, {{x0, 0, 0}, {x0, 0, 1}, {x0 + 1, 0, 1}, {x0 + 1, 0, 0}}, true);
        return mesh;
    };
    const Scene scene = sceneOf({floor(0.0f), floor(2.0f)});
    LightmapOptions options;
    options.texels_per_metre = 16.0;
    const auto texelsOf = [&](const std::vector<LightmapChart>& charts, uint32_t mesh) {
        double texels = 0.0;
        for (const LightmapChart& chart : charts)
            if (chart.mesh == mesh) texels += static_cast<double>(chart.width) * chart.height;
        return texels;
    };
    const std::vector<LightmapChart> even = buildLightmapCharts(scene, options);
    CHECK(texelsOf(even, 0) == 256.0);
    CHECK(texelsOf(even, 1) == 256.0);

    options.mesh_texel_scale = {0.5, 2.0};
    const std::vector<LightmapChart> scaled = buildLightmapCharts(scene, options);
    CHECK(texelsOf(scaled, 0) == 64.0);    // 8 x 8
    CHECK(texelsOf(scaled, 1) == 1024.0);  // 32 x 32
    for (const LightmapChart& chart : scaled) {
        CHECK(chart.texels_per_metre == (chart.mesh == 0 ? 8.0 : 32.0));
        checkFacesInside(chart);
    }
    // The budget's estimate counts the scaled texels too.
    CHECK(estimateLightmapTexels(scene, options) == doctest::Approx(64.0 + 1024.0));
    // A list shorter than the meshes leaves the rest at 1.
    options.mesh_texel_scale = {2.0};
    CHECK(texelsOf(buildLightmapCharts(scene, options), 1) == 256.0);
}
