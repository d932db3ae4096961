// Punctual light at points where surfaces meet (issue 27, the house's read-out faults): walls
// standing on a two-sided floor, lit by a directional light from under the floor. Every point
// above the floor is in the floor's shadow. Read from the point itself, a shadow ray at a wall's
// foot left through the floor within the ray caster's start offset, and the light under the
// floor lit the wall's foot: its vertices, the floor's corner vertices beside it (through the
// edge correction: the house's floor read 50 x its lightmap) and a one-texel line along the
// foot of the wall's lightmap chart (the seam fit pulled the partly covered texels there to the
// light read on the chart's edge).
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "bake/lightmap_bake.h"
#include "radbake.h"
#include "../export/temp_files.h"
#include "reference_mc.h"

using namespace radbake;
using testfs::TempDir;

namespace {

// A two-sided floor x, z in [0, 2] (y = 0, facing up), a wall on its far edge, a box x in [0, 2],
// y in [0, 0.955], z in [2, 2.1] (its -z face stands on the floor's edge: the floor's corners
// are its foot's), and a wall standing inside it, x in [0.5, 1.5], z in [1, 1.1] (its bottom on
// the floor, as a house's inner walls); lit by the directional lights `lights` (VRML nodes);
// every surface of reflectance `rho`. The walls' height is no whole number of texels, and their
// -z faces' charts run from the top, so the texels along their feet are partly covered, as the
// house's were.
std::string wallOnFloor(const std::string& lights, double rho) {
    const std::string grey = "diffuseColor " + std::to_string(rho) + " " + std::to_string(rho) + " " + std::to_string(rho);
    const auto box = [&](const std::string& at, const std::string& size) {
        return "Transform { translation " + at + " children Shape { appearance Appearance { material Material { " +
               grey + " } } geometry Box { size " + size + " } } }\n";
    };
    return "#VRML V2.0 utf8\n" + lights + "Shape { appearance Appearance { material Material { " + grey +
           " } }\n geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ 0 0 0, 0 0 2, 2 0 2, 2 0 0 ] }\n"
           " coordIndex [ 0 1 2 3 -1 ] } }\n" +
           box("1 0.4775 2.05", "2 0.955 0.1") + box("1 0.4775 1.05", "1 0.955 0.1");
}

// From under the floor, going up and towards +z: it faces the walls' -z faces (cos 1/sqrt 5) and
// the floor's underside, and every point of the -z faces is in the floor's shadow (the ray from
// height h meets the floor h / 2 before the wall).
const std::string kFromBelow = "DirectionalLight { direction 0 1 0.5 intensity 1 color 1 1 1 }\n";
// From above, going down and towards +z: the walls' -z faces get cos 1/sqrt 5, the floor 2/sqrt 5
// but in the inner wall's shadow (inShadow).
const std::string kFromAbove = "DirectionalLight { direction 0 -1 0.5 intensity 1 color 1 1 1 }\n";

Bake bakeText(const TempDir& dir, const std::string& scene) {
    BakeOptions options = BakeOptions::forQuality(Quality::Medium);
    options.lightmaps.texels_per_unit = 16.0;
    options.threading.threads = 2;
    Progress progress(false);
    Diagnostics diagnostics;
    Bake baked = bake(testfs::writeText(dir, "wall_on_floor.wrl", scene), options, progress, diagnostics);
    REQUIRE(std::string(toString(baked.status)) == "ok");
    REQUIRE(baked.lightmaps);
    return baked;
}

// Whether a floor point is in the inner wall's shadow from above, or within a texel of its edge.
bool inShadow(const DVec3& p) {
    const double margin = 1.0 / 16.0;
    return p.y < 1e-6 && p.x > 0.5 - margin && p.x < 1.5 + margin && p.z > 1.0 - margin;
}

// The unit normal of the first triangle of `mesh` that uses vertex v.
DVec3 vertexNormal(const Mesh& mesh, uint32_t v) {
    for (const UVec3& t : mesh.triangles)
        if (t.x == v || t.y == v || t.z == v)
            return glm::normalize(glm::cross(DVec3(mesh.positions[t.y]) - DVec3(mesh.positions[t.x]),
                                             DVec3(mesh.positions[t.z]) - DVec3(mesh.positions[t.x])));
    return DVec3(0.0);
}

// Over the floor's top (mesh 0) and the walls' -z faces (meshes 1 and 2): the largest
// |H / pi - expected| at vertices and at covered texels, `expected` by the face's normal, points
// in the inner wall's shadow from above left out.
struct Worst {
    double vertex = 0.0, texel = 0.0;
    double floor_vertex = 0.0;  // of the floor's vertices alone (its far corners are the edge wall's foot)
    size_t vertices = 0, texels = 0;
};
template <class Expected>
Worst worstOff(const Bake& baked, Expected&& expected) {
    Worst worst;
    const Scene& scene = *baked.scene;
    for (uint32_t m = 0; m < 3 && m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
            const DVec3 n = vertexNormal(mesh, v);
            if (!(n.y > 0.99 || n.z < -0.99) || inShadow(DVec3(mesh.positions[v]))) continue;
            const double off = std::abs(double(baked.vertices.values[m][v].x) - expected(n));
            worst.vertex = std::max(worst.vertex, off);
            if (m == 0) worst.floor_vertex = std::max(worst.floor_vertex, off);
            ++worst.vertices;
        }
    }
    const Lightmaps& lightmaps = baked.lightmaps->lightmaps;
    for (const LightmapChart& chart : lightmaps.layout.charts) {
        if (chart.mesh > 2 || chart.atlas < 0) continue;
        const LightmapImage& image = lightmaps.images[chart.atlas];
        for (int j = 0; j < chart.height; ++j)
            for (int i = 0; i < chart.width; ++i) {
                DVec2 p_plane;
                size_t face = 0;
                if (!texelSamplePoint(chart, i, j, p_plane, face)) continue;
                const DVec3 n = chart.faces[face].normal_world;
                if (!(n.y > 0.99 || n.z < -0.99) || inShadow(chart.faces[face].worldPoint(p_plane))) continue;
                const size_t at = static_cast<size_t>(chart.y + j) * image.width + chart.x + i;
                worst.texel = std::max(worst.texel, std::abs(double(image.rgb[3 * at]) - expected(n)));
                ++worst.texels;
            }
    }
    return worst;
}

}  // namespace

TEST_CASE("a wall on the edge of a floor lit from under it: dark at its foot, at the floor's corners and in the lightmap") {
    TempDir dir;
    const Bake baked = bakeText(dir, wallOnFloor(kFromBelow, 0.5));
    // The closed form is 0 everywhere above the floor; the light under it is 1 W/m^2, and the
    // foot of the wall read it at 1/sqrt 5 (0.14 as H / pi). (The floor's corners take it only
    // where the wall has light of its own: the test with a lamp, below.)
    const Worst worst = worstOff(baked, [](const DVec3&) { return 0.0; });
    CHECK(worst.vertices >= 8);
    CHECK(worst.texels >= 100);
    CHECK(worst.vertex < 1e-4);
    CHECK(worst.floor_vertex < 1e-4);
    CHECK(worst.texel < 1e-4);
    MESSAGE("from under the floor: worst vertex " << worst.vertex << " of " << worst.vertices << " (floor "
                                                  << worst.floor_vertex << "), worst texel " << worst.texel << " of "
                                                  << worst.texels);
}

TEST_CASE("a wall on the edge of a floor lit from above: its foot keeps the light (black surfaces, direct light only)") {
    TempDir dir;
    // Both lights: the one under the floor must not add to the wall's foot, nor the shadow ray's
    // new start take the light from above away.
    const Bake baked = bakeText(dir, wallOnFloor(kFromBelow + kFromAbove, 0.0));
    const auto expected = [](const DVec3& n) { return (n.z < -0.99 ? 1.0 : 2.0) / std::sqrt(5.0) / kPi; };
    const Worst worst = worstOff(baked, expected);
    CHECK(worst.vertices >= 8);
    CHECK(worst.texels >= 100);
    CHECK(worst.vertex < 1e-3 * expected(DVec3(0, 0, -1)));
    CHECK(worst.texel < 1e-3 * expected(DVec3(0, 0, -1)));
    MESSAGE("from above and under: worst vertex " << worst.vertex << ", worst texel " << worst.texel);
}

// The exhaustive gather (the read-out's reference, and the vertex bake's where leaves disagree)
// at the wall's foot: it reads the point lifted off the surfaces it touches, and the wall's own
// bottom face and the floor's underside (lit from under the floor) lifted it below the floor.
TEST_CASE("the exhaustive gather at a wall's foot on a floor lit from under it reads the dark side") {
    TempDir dir;
    const Bake baked = bakeText(dir, wallOnFloor(kFromBelow, 0.5));
    const Scene& scene = *baked.scene;
    const Mesh& wall = scene.meshes[1];
    double worst = 0.0;
    size_t points = 0;
    for (uint32_t t = 0; t < wall.triangles.size(); ++t) {
        const UVec3& tri = wall.triangles[t];
        const DVec3 a(wall.positions[tri.x]), b(wall.positions[tri.y]), c(wall.positions[tri.z]);
        const DVec3 n = glm::normalize(glm::cross(b - a, c - a));
        if (!(n.z < -0.99)) continue;
        // Its corners on the floor, and the middle of its edge on the floor.
        std::vector<DVec3> foot;
        for (const DVec3& corner : {a, b, c})
            if (corner.y == 0.0) foot.push_back(corner);
        if (foot.size() == 2) foot.push_back(0.5 * (foot[0] + foot[1]));
        for (const DVec3& p : foot) {
            const DVec3 h = surfaceIrradiance(*baked.solution, baked.options.readout, p, n, 1, t);
            worst = std::max(worst, std::max({h.x, h.y, h.z}));
            ++points;
        }
    }
    CHECK(points >= 4);
    CHECK(worst < 1e-4);
    MESSAGE("exhaustive gather at the wall's foot: worst H " << worst << " of " << points << " points");
}

// The same with the wall one face, a pentagon whose fan of triangles has a sliver along its foot
// (as house.wrl's gables, whose polygons take in the roof slab's 6 cm end): read from a step
// towards the triangle's centroid or off the triangle's own edges, a point on the floor's line
// stayed within 1/300 of the step of the floor's plane, and the light under the floor reached
// it again.
TEST_CASE("a wall whose foot is a sliver triangle, on a floor lit from under it: dark at its foot") {
    TempDir dir;
    const std::string scene =
        "#VRML V2.0 utf8\n" + kFromBelow +
        "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
        " geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ 0 0 0, 0 0 2, 2 0 2, 2 0 0 ] }\n"
        " coordIndex [ 0 1 2 3 -1 ] } }\n"
        "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } }\n"
        " geometry IndexedFaceSet { coord Coordinate { point [ 0 0 2, 2 0 2, 2 0.955 2, 0 0.955 2, 0 0.003 2 ] }\n"
        " coordIndex [ 4 3 2 1 0 -1 ] } }\n";
    const Bake baked = bakeText(dir, scene);
    const Worst worst = worstOff(baked, [](const DVec3&) { return 0.0; });
    CHECK(worst.vertices >= 8);
    CHECK(worst.texels >= 100);
    CHECK(worst.vertex < 1e-4);
    CHECK(worst.texel < 1e-4);
    MESSAGE("sliver foot: worst vertex " << worst.vertex << " of " << worst.vertices << ", worst texel " << worst.texel
                                         << " of " << worst.texels);
}

// With a lamp above the floor the walls have light of their own, and the floor's corners at the
// edge wall's foot take the edge correction from the wall's light there: where that read the
// light under the floor, the corners read it too (the house's floor, 50 x its lightmap).
TEST_CASE("a wall on the edge of a floor lit from under it and by a lamp: its foot and the floor's corners against the Monte Carlo reference") {
    TempDir dir;
    const std::string lamp =
        "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 1 1 1 } }\n"
        " geometry IndexedFaceSet { coord Coordinate { point [ 0.8 1.5 0.3, 1.2 1.5 0.3, 1.2 1.5 0.7, 0.8 1.5 0.7 ] }\n"
        " coordIndex [ 0 1 2 3 -1 ] } }\n";
    const Bake baked = bakeText(dir, wallOnFloor(kFromBelow, 0.5) + lamp);
    const Scene& scene = *baked.scene;
    // The floor's two corners at the edge wall's foot and the wall's -z face there, each nudged
    // 1e-4 into its own face, as tools/vertex_probes does.
    struct Corner {
        uint32_t mesh;
        DVec3 at, normal, nudge;
    };
    std::vector<Corner> corners;
    for (const double x : {0.0, 2.0}) {
        const DVec3 in(x == 0.0 ? 1e-4 : -1e-4, 0, 0);
        corners.push_back({0, {x, 0, 2}, {0, 1, 0}, in + DVec3(0, 0, -1e-4)});
        corners.push_back({1, {x, 0, 2}, {0, 0, -1}, in + DVec3(0, 1e-4, 0)});
    }
    std::vector<reference::McProbe> probes;
    std::vector<double> baked_h;
    for (const Corner& c : corners) {
        const Mesh& mesh = scene.meshes[c.mesh];
        double h = -1.0;
        for (uint32_t v = 0; v < mesh.positions.size(); ++v)
            if (glm::length(DVec3(mesh.positions[v]) - c.at) < 1e-6 && glm::dot(vertexNormal(mesh, v), c.normal) > 0.99)
                h = kPi * baked.vertices.values[c.mesh][v].x;
        REQUIRE(h >= 0.0);
        probes.push_back({c.at + c.nudge, c.normal});
        baked_h.push_back(h);
    }
    reference::McOptions mc;
    mc.samples = 16384;
    mc.threads = 2;
    const std::vector<reference::McProbeResult> expected = reference::estimateProbes(reference::McBvh(scene), probes, mc);
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(probes[i].position);
        CAPTURE(probes[i].normal);
        const double mean = expected[i].irradiance.x;
        REQUIRE(mean > 0.0);
        CHECK(expected[i].standard_error.x < 0.02 * mean);
        const double gather =
            probeIrradiance(*baked.solution, baked.options.readout, probes[i].position, probes[i].normal).x;
        MESSAGE("vertex H " << baked_h[i] << ", exhaustive gather at the probe " << gather << ", reference " << mean
                            << " +- " << expected[i].standard_error.x);
        // The light under the floor read the floor's corners 12 x the reference and the wall's foot
        // 90 x. What is left (the vertices 15-25 % low) is the read-out's at this corner: the
        // wall's foot reads low in the gather too, and the edge correction takes the floor's
        // corner down with it.
        CHECK(std::abs(baked_h[i] / mean - 1.0) < 0.3);
    }
}

// A shelf (two-sided, y = 1, x and z in [0, 1]) in the corner of two walls, each wall two
// coincident two-sided boards facing opposite ways (as graz.wrl's furniture is built), over an
// emitting floor that reaches behind the walls. The exhaustive gather at the corner of the
// shelf's underside lifts the point off its own plane and off the boards' sides the shelf stands
// in front of. Lifted off every side (liftOffSurfaces: the boards' two sides cancel), it stayed in
// the boards' planes and saw the floor behind them through the rays' start offset: 2.7 against
// 1.3 a little way in. The corner's light is the limit of the underside's from inside the face.
TEST_CASE("the exhaustive gather at a shelf's underside in the corner of two-sided boards: the limit from inside the face") {
    const std::string grey = "material Material { diffuseColor 0.5 0.5 0.5 }";
    const auto face = [&](const std::string& points) {
        return "Shape { appearance Appearance { " + grey + " }\n geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ " +
               points + " ] } coordIndex [ 0 1 2 3 -1 ] } }\n";
    };
    const std::string scene =
        "#VRML V2.0 utf8\n"
        "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 1 1 1 } }\n"
        " geometry IndexedFaceSet { solid TRUE coord Coordinate { point [ -2 0 -2, -2 0 3, 3 0 3, 3 0 -2 ] }\n"
        " coordIndex [ 0 1 2 3 -1 ] } }\n" +
        face("0 1 0, 0 1 1, 1 1 1, 1 1 0") +                                   // the shelf
        face("0 0.5 0, 0 0.5 1, 0 1.5 1, 0 1.5 0") + face("0 1.5 0, 0 1.5 1, 0 0.5 1, 0 0.5 0") +  // wall x = 0
        face("0 0.5 0, 0 1.5 0, 1 1.5 0, 1 0.5 0") + face("1 0.5 0, 1 1.5 0, 0 1.5 0, 0 0.5 0");   // wall z = 0
    TempDir dir;
    const Bake baked = bakeText(dir, scene);
    const Scene& s = *baked.scene;
    // The shelf's underside: its back twin's triangle holding the corner (0, 1, 0).
    bool found = false;
    for (uint32_t m = 0; m < s.meshes.size() && !found; ++m) {
        const Mesh& mesh = s.meshes[m];
        for (uint32_t t = 0; t < mesh.triangles.size() && !found; ++t) {
            const UVec3& tri = mesh.triangles[t];
            const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
            const DVec3 n = glm::normalize(glm::cross(b - a, c - a));
            if (!(n.y < -0.99) || !(std::abs(a.y - 1.0) < 1e-6)) continue;
            const DVec3 corner(0.0, 1.0, 0.0);
            if (glm::length(a - corner) > 1e-6 && glm::length(b - corner) > 1e-6 && glm::length(c - corner) > 1e-6) continue;
            found = true;
            const DVec3 at_corner = surfaceIrradiance(*baked.solution, baked.options.readout, corner, n, m, t);
            const DVec3 inside = surfaceIrradiance(*baked.solution, baked.options.readout, DVec3(0.02, 1.0, 0.02), n, m, t);
            MESSAGE("underside H at the corner " << at_corner.x << ", 2 cm in " << inside.x);
            CHECK(inside.x > 0.1);
            CHECK(at_corner.x == doctest::Approx(inside.x).epsilon(0.15));
        }
    }
    CHECK(found);
}
