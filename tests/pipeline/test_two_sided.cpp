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
