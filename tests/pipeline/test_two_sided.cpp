// Two-sided surfaces (scene/two_sided.h) through the whole bake, against closed forms at probes
// and at output vertices (issue 13): the outward two-sided furnace, its one-sided twin, a thin
// wall lit from one side, each side's lightmap charts and glb mesh.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "radbake.h"
#include "export/probes.h"
#include "../export/temp_files.h"

using namespace radbake;

namespace {

std::string analyticFile(const std::string& name) { return std::string(RADBAKE_SOURCE_DIR) + "/scenes/analytic/" + name; }

struct Expected {
    std::vector<Probe> probes;
    std::vector<double> h;  // grey expected H per probe
    std::vector<double> rel_tol;
};

// The probes and exact answers of an analytic scene (x,y,z,nx,ny,nz,r,g,b,rel_tol).
Expected readExpected(const std::string& name) {
    Expected out;
    std::ifstream in(analyticFile(name + ".expected.csv"));
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string field;
        double v[10] = {};
        for (int k = 0; k < 10 && std::getline(fields, field, ','); ++k) v[k] = std::stod(field);
        Probe probe;
        probe.position = DVec3(v[0], v[1], v[2]);
        probe.normal = DVec3(v[3], v[4], v[5]);
        out.probes.push_back(probe);
        out.h.push_back(v[6]);
        out.rel_tol.push_back(v[9]);
    }
    REQUIRE(!out.probes.empty());
    return out;
}

BakeOptions defaultOptions(std::vector<Probe> probes, bool lightmaps = false) {
    BakeOptions options;  // the default quality
    options.lightmaps.enabled = lightmaps;
    options.threading.threads = 2;
    options.probes = std::move(probes);
    return options;
}

template <class Input>
Bake bakeQuietly(Input input, const BakeOptions& options) {
    Progress progress(false);
    Diagnostics diagnostics;
    Bake result = bake(std::move(input), options, progress, diagnostics);
    for (const Diagnostic& d : diagnostics.all())
        if (d.severity == Severity::Error) MESSAGE(formatDiagnostic(d));
    REQUIRE(result.ok());
    return result;
}

double grey(const DVec3& v) { return (v.x + v.y + v.z) / 3.0; }

// Largest relative error of a mesh's baked vertex values (H / pi) against h / pi.
double worstVertexError(const Bake& b, size_t mesh, double h) {
    double worst = 0.0;
    for (const Vec3& value : b.vertices.values[mesh])
        worst = std::max(worst, std::abs(grey(DVec3(value)) * kPi - h) / h);
    return worst;
}

double largestVertexValue(const Bake& b, size_t mesh) {
    double largest = 0.0;
    for (const Vec3& value : b.vertices.values[mesh]) largest = std::max(largest, double(std::max({value.x, value.y, value.z})));
    return largest;
}

}  // namespace

TEST_CASE("two-sided furnace: the outward solid FALSE cube is a furnace inside, H = 2 pi at probes and vertices") {
    const Expected expected = readExpected("furnace_two_sided");
    const Bake b = bakeQuietly(analyticFile("furnace_two_sided.wrl"), defaultOptions(expected.probes));
    const double h = 2.0 * kPi;
    REQUIRE(b.probe_irradiance.size() == expected.probes.size());
    for (size_t i = 0; i < expected.probes.size(); ++i) {
        CAPTURE(i);
        CHECK(expected.h[i] == doctest::Approx(h).epsilon(1e-12));
        CHECK(std::abs(grey(b.probe_irradiance[i]) - h) / h <= 0.02);
    }
    // Six faces read, six back twins baked after them: the backs hold the furnace, the fronts
    // (outside, seeing nothing) hold 0.
    const Scene& scene = *b.scene;
    REQUIRE(scene.meshes.size() == 12);
    CHECK(b.report.two_sided_meshes == 6);
    for (size_t m = 0; m < 6; ++m) {
        CAPTURE(m);
        REQUIRE(scene.meshes[m + 6].back);
        CHECK(scene.meshes[m].twin == m + 6);
        CHECK(worstVertexError(b, m + 6, h) <= 0.02);
        CHECK(largestVertexValue(b, m) == 0.0);
    }
}

TEST_CASE("one-sided stays one-sided: the same outward cube with solid TRUE reads 0 inside") {
    const Expected expected = readExpected("furnace_two_sided");
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(analyticFile("furnace_two_sided.wrl"), ImportOptions{}, diagnostics);
    REQUIRE(scene);
    for (Mesh& mesh : scene->meshes) mesh.solid = true;
    const Bake b = bakeQuietly(std::move(*scene), defaultOptions(expected.probes));
    CHECK(b.scene->meshes.size() == 6);  // no twins
    CHECK(b.report.two_sided_meshes == 0);
    for (size_t i = 0; i < b.probe_irradiance.size(); ++i) {
        CAPTURE(i);
        CHECK(grey(b.probe_irradiance[i]) == 0.0);
    }
    for (size_t m = 0; m < 6; ++m) CHECK(largestVertexValue(b, m) == 0.0);
}

TEST_CASE("a thin solid FALSE wall lit from one side is lit on that side and dark on the other") {
    const Expected expected = readExpected("thin_wall_two_sided");
    std::vector<Probe> probes = expected.probes;
    for (const Probe& lit : expected.probes) {  // the same points on the back
        Probe back = lit;
        back.normal = -lit.normal;
        probes.push_back(back);
    }
    const Bake b = bakeQuietly(analyticFile("thin_wall_two_sided.wrl"), defaultOptions(probes));
    const size_t n = expected.probes.size();
    REQUIRE(b.probe_irradiance.size() == 2 * n);
    for (size_t i = 0; i < n; ++i) {
        CAPTURE(i);
        CHECK(std::abs(grey(b.probe_irradiance[i]) - expected.h[i]) / expected.h[i] <= expected.rel_tol[i]);
        CHECK(grey(b.probe_irradiance[n + i]) == 0.0);
    }
    // Meshes: the emitter, the wall, the wall's back twin.
    const Scene& scene = *b.scene;
    REQUIRE(scene.meshes.size() == 3);
    REQUIRE(scene.meshes[2].back);
    CHECK(scene.meshes[2].twin == 1);
    CHECK(scene.meshes[2].name == scene.meshes[1].name + " (back)");
    CHECK(largestVertexValue(b, 1) > 0.1);
    CHECK(largestVertexValue(b, 2) == 0.0);
}

TEST_CASE("outputs give each side its value: lightmap charts per side and a flipped glb mesh") {
    const Expected expected = readExpected("thin_wall_two_sided");
    BakeOptions options = defaultOptions({}, true);
    options.solver = SolverOptions::forQuality(Quality::Draft);
    const Bake b = bakeQuietly(analyticFile("thin_wall_two_sided.wrl"), options);
    REQUIRE(b.lightmaps);
    const Lightmaps& lightmaps = b.lightmaps->lightmaps;
    // Texel sums of each mesh's charts: the wall's front is lit, its back is dark, and both
    // have charts of their own.
    std::vector<double> sum(3, 0.0);
    std::vector<size_t> charts(3, 0), texels(3, 0);
    for (const LightmapChart& chart : lightmaps.layout.charts) {
        REQUIRE(chart.mesh < 3);
        ++charts[chart.mesh];
        const LightmapImage& image = lightmaps.images.at(static_cast<size_t>(chart.atlas));
        for (int y = chart.y; y < chart.y + chart.height; ++y)
            for (int x = chart.x; x < chart.x + chart.width; ++x) {
                const size_t k = (static_cast<size_t>(y) * image.width + x) * 3;
                sum[chart.mesh] += image.rgb[k] + image.rgb[k + 1] + image.rgb[k + 2];
                ++texels[chart.mesh];
            }
    }
    CHECK(charts[1] > 0);
    CHECK(charts[2] > 0);
    CHECK(texels[2] == texels[1]);  // the same surface, the same density
    CHECK(sum[1] > 0.0);
    CHECK(sum[2] == 0.0);

    testfs::TempDir out;
    Diagnostics diagnostics;
    REQUIRE(writeBake(b, out.path, diagnostics));
    const std::string glb = testfs::readBytes(out.path / "thin_wall_two_sided.glb");
    // Both sides single-sided (glTF's default), the back a mesh of its own naming its front.
    CHECK(glb.find("\"doubleSided\":true") == std::string::npos);
    CHECK(glb.find("\"radbake_back_of\"") != std::string::npos);
    CHECK(glb.find(" (back)\"") != std::string::npos);
}

// --- closed two-sided meshes (settleClosedTwoSided) -----------------------------------------

namespace {

// A room [-2,2] x [-2,2] x [0,3] (one-sided walls facing in, an emitting ceiling panel) with a
// box [-0.5,0.5]^2 x [0,1] on its floor, an IndexedFaceSet of six outward quads that are
// `solid` as given; `inside` is put inside the box.
std::string roomWithBox(const std::string& box_solid, const std::string& inside = "") {
    return "#VRML V2.0 utf8\n"
           "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
           "  geometry IndexedFaceSet { coord Coordinate { point [-2 -2 0, 2 -2 0, 2 2 0, -2 2 0,"
           " -2 -2 3, 2 -2 3, 2 2 3, -2 2 3] }\n"
           "    coordIndex [0 1 2 3 -1, 4 7 6 5 -1, 0 4 5 1 -1, 1 5 6 2 -1, 2 6 7 3 -1, 3 7 4 0 -1] } }\n"
           "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 1 1 1 } }\n"
           "  geometry IndexedFaceSet { coord Coordinate { point [-1 -1 2.99, 1 -1 2.99, 1 1 2.99, -1 1 2.99] }\n"
           "    coordIndex [0 3 2 1 -1] } }\n"
           "DEF Crate Shape { appearance Appearance { material Material { diffuseColor 0.7 0.7 0.7 } }\n"
           "  geometry IndexedFaceSet { solid " + box_solid + "\n"
           "    coord Coordinate { point [-0.5 -0.5 0, 0.5 -0.5 0, 0.5 0.5 0, -0.5 0.5 0,"
           " -0.5 -0.5 1, 0.5 -0.5 1, 0.5 0.5 1, -0.5 0.5 1] }\n"
           "    coordIndex [0 3 2 1 -1, 4 5 6 7 -1, 0 1 5 4 -1, 1 2 6 5 -1, 2 3 7 6 -1, 3 0 4 7 -1] } }\n" +
           inside;
}

Bake bakeText(const std::string& text, const BakeOptions& options) {
    testfs::TempDir dir;
    const std::string path = (dir.path / "room.wrl").string();
    std::ofstream(path) << text;
    return bakeQuietly(path, options);
}

}  // namespace

TEST_CASE("a closed solid FALSE box in a lit room gets no back twin and bakes as the solid TRUE box") {
    const std::vector<Probe> probes = {{DVec3(0.5, 0.0, 0.5), DVec3(1, 0, 0), {}},   // the box's side, outside
                                       {DVec3(0.0, 0.0, 1.0), DVec3(0, 0, 1), {}},   // its top
                                       {DVec3(0.0, 0.0, 0.5), DVec3(1, 0, 0), {}}};  // inside it
    const Bake two_sided = bakeText(roomWithBox("FALSE"), defaultOptions(probes));
    const Bake one_sided = bakeText(roomWithBox("TRUE"), defaultOptions(probes));
    REQUIRE(two_sided.scene->meshes.size() == 3);  // no twin
    CHECK(two_sided.report.two_sided_meshes == 0);
    CHECK(two_sided.report.two_sided_closed_meshes == 1);
    CHECK(two_sided.scene->meshes[2].closed_two_sided);
    CHECK(one_sided.report.two_sided_closed_meshes == 0);
    // The same light, vertex by vertex and at the probes.
    REQUIRE(two_sided.vertices.values.size() == one_sided.vertices.values.size());
    for (size_t m = 0; m < 3; ++m) {
        REQUIRE(two_sided.vertices.values[m].size() == one_sided.vertices.values[m].size());
        for (size_t v = 0; v < two_sided.vertices.values[m].size(); ++v) {
            CAPTURE(m);
            CAPTURE(v);
            const double a = grey(DVec3(two_sided.vertices.values[m][v])), b = grey(DVec3(one_sided.vertices.values[m][v]));
            CHECK(std::abs(a - b) <= 1e-6 * std::max(1.0, b));
        }
    }
    CHECK(largestVertexValue(two_sided, 2) > 0.01);  // lit outside
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(i);
        CHECK(std::abs(grey(two_sided.probe_irradiance[i]) - grey(one_sided.probe_irradiance[i])) <=
              1e-6 * std::max(1.0, grey(one_sided.probe_irradiance[i])));
    }
    CHECK(grey(two_sided.probe_irradiance[0]) > 0.01);
    // probe 2 (inside the box) matches the solid TRUE box's too; it is not exactly 0 there today
    // (a few thousandths through the probe gather, the same one-sided or not).

    // stats.json says so.
    testfs::TempDir out;
    Diagnostics diagnostics;
    REQUIRE(writeBake(two_sided, out.path, diagnostics));
    CHECK(testfs::readBytes(out.path / "stats.json").find("\"two_sided_closed_meshes\": 1") != std::string::npos);
}

TEST_CASE("a closed solid FALSE box with a PointLight inside keeps its back twin and is lit inside") {
    const std::vector<Probe> probes = {{DVec3(0.0, 0.0, 0.01), DVec3(0, 0, 1), {}}};  // the box's floor, inside
    const Bake b = bakeText(roomWithBox("FALSE", "PointLight { location 0 0 0.5 intensity 1 }\n"), defaultOptions(probes));
    const Scene& scene = *b.scene;
    REQUIRE(scene.meshes.size() == 4);
    CHECK(b.report.two_sided_meshes == 1);
    CHECK(b.report.two_sided_closed_meshes == 0);
    REQUIRE(scene.meshes[3].back);
    CHECK(scene.meshes[3].twin == 2);
    CHECK(largestVertexValue(b, 3) > 0.01);  // the backs, inside: lit by the light
    CHECK(grey(b.probe_irradiance[0]) > 0.01);
}

TEST_CASE("the outward two-sided furnace and the open thin wall keep their twins") {
    // The furnace emits from its backs into its own volume; the wall is open.
    for (const char* name : {"furnace_two_sided.wrl", "thin_wall_two_sided.wrl"}) {
        CAPTURE(name);
        Diagnostics diagnostics;
        std::optional<Scene> scene = importScene(analyticFile(name), ImportOptions{}, diagnostics);
        REQUIRE(scene);
        const size_t two_sided = summarize(*scene).two_sided_meshes;
        CHECK(two_sided > 0);
        CHECK(addBackTwins(*scene) == two_sided);
        CHECK(summarize(*scene).two_sided_closed_meshes == 0);
    }
}

TEST_CASE("a closed two-sided emitter in one mesh keeps its twin: the outward furnace as one IndexedFaceSet") {
    // The unit cube's six faces facing out in one mesh, emitting 1 and reflecting 0.5 on both
    // sides: closed, but its backs emit into its own volume, which is the furnace, H = 2 pi.
    const std::string cube =
        "#VRML V2.0 utf8\n"
        "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 emissiveColor 1 1 1 } }\n"
        "  geometry IndexedFaceSet { solid FALSE\n"
        "    coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0, 0 0 1, 1 0 1, 1 1 1, 0 1 1] }\n"
        "    coordIndex [0 3 2 1 -1, 4 5 6 7 -1, 0 1 5 4 -1, 1 2 6 5 -1, 2 3 7 6 -1, 3 0 4 7 -1] } }\n";
    const std::vector<Probe> probes = {{DVec3(0.5), DVec3(0, 0, 1), {}}, {DVec3(0.5), DVec3(1, 0, 0), {}}};
    const Bake b = bakeText(cube, defaultOptions(probes));
    REQUIRE(b.scene->meshes.size() == 2);
    CHECK(b.report.two_sided_meshes == 1);
    CHECK(b.report.two_sided_closed_meshes == 0);
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(i);
        CHECK(std::abs(grey(b.probe_irradiance[i]) - 2.0 * kPi) / (2.0 * kPi) <= 0.02);
    }
    CHECK(worstVertexError(b, 1, 2.0 * kPi) <= 0.02);
    CHECK(largestVertexValue(b, 0) == 0.0);  // outside sees nothing
}

TEST_CASE("two touching back-to-back two-sided slabs: the backs in the gap are dark, no light passes, few iterations") {
    // A white (0.999) slab made of two solid FALSE quads 1e-5 apart, the upper facing up, the
    // lower facing down, lit from straight above (E = 1) over a black floor. Their back twins face
    // each other across the gap: a two-surface furnace at rho = 0.999 unless they are dark.
    // Closed forms: the top reads H / pi = 1 / pi (it sees only the sky), the underside 0 (the
    // floor is black and nothing passes the slab), and the covered backs reflect nothing.
    testfs::TempDir dir;
    const auto quad = [](float y, bool up) {
        const std::string h = std::to_string(y);
        return std::string("Shape { appearance Appearance { material Material { diffuseColor 1 1 1 } }\n") +
               " geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ -1 " + h + " -1, -1 " + h + " 1, 1 " + h +
               " 1, 1 " + h + " -1 ] } coordIndex [ " + (up ? "0 1 2 3" : "3 2 1 0") + " -1 ] } }\n";
    };
    const std::string path = testfs::writeText(
        dir, "slabs.wrl",
        "#VRML V2.0 utf8\nDirectionalLight { direction 0 -1 0 }\n" + quad(1.0f, true) + quad(1.0f - 1e-5f, false) +
            "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 } }\n"
            " geometry IndexedFaceSet { coord Coordinate { point [ -3 0 -3, -3 0 3, 3 0 3, 3 0 -3 ] } coordIndex [ 0 1 2 3 -1 ] } }\n");
    const Bake b = bakeQuietly(path, defaultOptions({}));
    const Scene& scene = *b.scene;
    REQUIRE(scene.meshes.size() == 5);  // two slabs, the floor, two twins
    CHECK(scene.covered_back_polygons == 2);
    for (uint32_t front : {0u, 1u}) CHECK(polygonReflectance(scene, scene.meshes[scene.meshes[front].twin], 0) == Vec3(0.0f));
    CHECK(worstVertexError(b, 0, 1.0) < 0.01);   // the top
    CHECK(largestVertexValue(b, 1) < 1e-6);      // the underside
    REQUIRE(b.solution);
    CHECK(b.solution->stats.converged);
    CHECK(b.solution->stats.iterations <= 12);
}
