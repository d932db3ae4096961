// Edges, corners and contact lines against closed forms (issue 13), from file to bake at the
// default quality: output vertices hold the limit of the value from inside their own face (the
// point nudged 1e-4 into it, as a path tracer gives), probes near an edge the value where they are.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "bake/lightmap_mesh.h"
#include "bake/lightmap_seams.h"
#include "export/mesh_attributes.h"
#include "radbake.h"
#include "radiosity/form_factor.h"
#include "readout/reconstruct.h"
#include "visibility/ray_caster.h"
#include "../export/temp_files.h"
#include "reference_mc.h"

using namespace radbake;
using testfs::TempDir;

namespace {

constexpr double kNudge = 1e-4;

Bake bakeFile(const std::string& path, std::optional<std::vector<Probe>> probes = std::nullopt,
              EdgeCorrection edge_correction = ReadoutOptions{}.edge_correction) {
    BakeOptions options = BakeOptions::forQuality(Quality::Medium);
    options.readout.edge_correction = edge_correction;
    options.lightmaps.enabled = false;
    options.threading.threads = 2;
    options.probes = std::move(probes);
    Progress progress(false);
    Diagnostics diagnostics;
    Bake baked = bake(path, options, progress, diagnostics);
    for (const Diagnostic& d : diagnostics.all()) MESSAGE(formatDiagnostic(d));
    REQUIRE(std::string(toString(baked.status)) == "ok");
    return baked;
}

// An IndexedFaceSet of n x n quads over the rectangle origin + [0, 1] u + [0, 1] v, facing u x v.
std::string gridShape(const std::string& material, DVec3 origin, DVec3 u, DVec3 v, int n) {
    std::ostringstream out;
    out << "Shape { appearance Appearance { material Material { " << material << " } }\n"
        << " geometry IndexedFaceSet { creaseAngle 0 coord Coordinate { point [\n";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const DVec3 p = origin + (double(i) / n) * u + (double(j) / n) * v;
            out << "  " << p.x << ' ' << p.y << ' ' << p.z << ",\n";
        }
    out << " ] }\n coordIndex [\n";
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i;
            out << "  " << a << ' ' << a + 1 << ' ' << a + n + 2 << ' ' << a + n + 1 << " -1,\n";
        }
    out << " ] } }\n";
    return out.str();
}

// The point moved kNudge into the axis-aligned rectangle [lo, hi] (one coordinate of lo and hi equal).
DVec3 nudgeInto(DVec3 p, DVec3 lo, DVec3 hi) {
    for (int k = 0; k < 3; ++k)
        if (hi[k] > lo[k]) p[k] = std::clamp(p[k], lo[k] + kNudge, hi[k] - kNudge);
    return p;
}

Probe probeAt(DVec3 position, DVec3 normal) {
    Probe probe;
    probe.position = position;
    probe.normal = normal;
    return probe;
}

struct ErrorTally {
    double worst = 0.0, sum_squares = 0.0;
    size_t count = 0;
    void add(double value, double expected) {
        const double e = value / expected - 1.0;
        worst = std::max(worst, std::abs(e));
        sum_squares += e * e;
        ++count;
    }
    double rms() const { return count ? std::sqrt(sum_squares / double(count)) : 0.0; }
};

// A white unit room facing in, each wall an n x n grid (so its edges and corners are shared
// vertices), lit by a 0.2 x 0.2 lamp facing down at lamp_y.
std::string tiledRoom(int n = 4, double lamp_y = 0.9) {
    const std::string white = "diffuseColor 0.75 0.75 0.75";
    return "#VRML V2.0 utf8\n" + gridShape(white, {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, n) +
           gridShape(white, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, n) + gridShape(white, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, n) +
           gridShape(white, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, n) + gridShape(white, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n) +
           gridShape(white, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, n) +
           gridShape("diffuseColor 0 0 0 emissiveColor 10 10 10", {0.4, lamp_y, 0.4}, {0.2, 0, 0}, {0, 0, 0.2}, 1);
}

// H (red) at a point just under a ceiling (facing -y) from the solution's radiosities with exact
// visibility: `rays` cosine-distributed rays, each reading the leaf it hits.
double ceilingGather(const Solution& s, const LinkReconstruction& links, const DVec3& point, int rays, uint64_t seed) {
    const DVec3 o = point + DVec3(0, -1e-5, 0);
    uint64_t state = seed;
    const auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) / double(1ull << 53);
    };
    double exact = 0.0;
    for (int k = 0; k < rays; ++k) {
        const double u1 = uniform(), u2 = uniform(), r = std::sqrt(u1), phi = 2.0 * kPi * u2;
        const DVec3 d(r * std::cos(phi), -std::sqrt(std::max(0.0, 1.0 - u1)), r * std::sin(phi));
        const auto hit = s.rays->closestHit(o, d, 1e30);
        if (!hit) continue;
        const uint32_t leaf = links.leafAt(hit->triangle.mesh, hit->triangle.triangle, o + hit->t * d);
        if (leaf != kNoElement && glm::dot(s.elements[leaf].normal, d) < 0.0) exact += s.elements[leaf].radiosity.x / rays;
    }
    return exact;
}

}  // namespace

// A black floor x in [0, 2], z in [-1, 1] (y = 0, facing up) hinged at x = 0 to an emitting wall
// (radiance 1, black, y in [0, 1], facing +x). H / pi at a floor point is its form factor to the
// wall: 1/2 on the hinge (the limit from inside the floor), falling off with distance.
TEST_CASE("a 90-degree hinge between an emitter and a floor: vertices and probes on and near it") {
    TempDir dir;
    const DVec3 floor_lo(0, 0, -1), floor_hi(2, 0, 1);
    const std::vector<DVec3> wall = {{0, 0, -1}, {0, 0, 1}, {0, 1, 1}, {0, 1, -1}};  // faces +x
    const std::string path = testfs::writeText(
        dir, "hinge.wrl",
        "#VRML V2.0 utf8\n" + gridShape("diffuseColor 0 0 0", {0, 0, 1}, {2, 0, 0}, {0, 0, -2}, 8) +
            gridShape("diffuseColor 0 0 0 emissiveColor 1 1 1", {0, 0, 1}, {0, 0, -2}, {0, 1, 0}, 4));
    std::vector<Probe> probes;
    for (const double x : {0.0, 1e-3, 1e-2, 0.1, 0.5})
        for (const double z : {0.0, 0.9}) probes.push_back(probeAt(DVec3(x, 0, z), DVec3(0, 1, 0)));
    const Bake baked = bakeFile(path, probes);
    const Mesh& floor = baked.scene->meshes[0];
    const std::vector<Vec3>& values = baked.vertices.values[0];
    ErrorTally vertices, on_hinge, near;
    for (size_t v = 0; v < floor.positions.size(); ++v) {
        // Not the floor's two corners at the wall's ends: there the limit depends on the way in
        // (1/4 of the wall along the hinge, 3/8 along the diagonal a path tracer nudges in); the
        // vertex bake reads 1/4 (the note, session 7).
        if (floor.positions[v].x == 0.0f && std::abs(floor.positions[v].z) == 1.0f) continue;
        const DVec3 p = nudgeInto(DVec3(floor.positions[v]), floor_lo, floor_hi);
        const double expected = pointPolygonFormFactor(p, {0, 1, 0}, wall, {1, 0, 0});
        CAPTURE(floor.positions[v].x);
        CAPTURE(floor.positions[v].z);
        CAPTURE(values[v].x);
        CAPTURE(expected);
        CHECK(std::abs(values[v].x / expected - 1.0) < 0.02);
        (floor.positions[v].x == 0.0f ? on_hinge : vertices).add(values[v].x, expected);
    }
    CHECK(on_hinge.count == 7);
    for (size_t i = 0; i < probes.size(); ++i) {
        const DVec3 p = nudgeInto(probes[i].position, floor_lo, floor_hi);
        const double expected = kPi * pointPolygonFormFactor(p, {0, 1, 0}, wall, {1, 0, 0});
        CAPTURE(probes[i].position.x);
        CAPTURE(probes[i].position.z);
        CHECK(std::abs(baked.probe_irradiance[i].x / expected - 1.0) < 0.02);
        near.add(baked.probe_irradiance[i].x, expected);
    }
    MESSAGE("hinge: worst vertex on it " << on_hinge.worst << ", elsewhere " << vertices.worst << "; worst probe "
                                         << near.worst);
}

// A black 1 m cube standing on a 20 x 20 m emitting floor (radiance 1, black). A side face's H / pi
// is its unoccluded form factor to the floor (the cube is behind it): 1/2 on its bottom edge, the
// limit from inside the face; probes 1 mm above that edge, facing away, within 2 %.
TEST_CASE("a black block standing on an emitting floor: its bottom edges hold 1/2, probes 1 mm up the closed form") {
    TempDir dir;
    const std::vector<DVec3> floor = {{-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}};
    const std::string path = testfs::writeText(
        dir, "block_on_floor.wrl",
        "#VRML V2.0 utf8\n"
        "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 emissiveColor 1 1 1 } }\n"
        " geometry IndexedFaceSet { coord Coordinate { point [ -10 0 -10, -10 0 10, 10 0 10, 10 0 -10 ] }\n"
        "  coordIndex [ 0 1 2 3 -1 ] } }\n"
        "Transform { translation 0 0.5 0 children Shape {\n"
        " appearance Appearance { material Material { diffuseColor 0 0 0 } } geometry Box { size 1 1 1 } } }\n");
    std::vector<Probe> probes;
    for (const double z : {0.0, 0.3, 0.49}) {
        probes.push_back(probeAt(DVec3(0.5, 1e-3, z), DVec3(1, 0, 0)));
        probes.push_back(probeAt(DVec3(z, 1e-3, -0.5), DVec3(0, 0, -1)));
    }
    const Bake baked = bakeFile(path, probes);
    const Mesh& cube = baked.scene->meshes[1];
    REQUIRE(cube.positions.size() == 24);
    const std::vector<Vec3>& values = baked.vertices.values[1];
    const std::vector<Vec3> normals = vertexNormals(cube);
    ErrorTally bottom_edge, sides;
    for (size_t v = 0; v < cube.positions.size(); ++v) {
        const DVec3 n(normals[v]);
        if (std::abs(n.y) > 0.5) continue;  // top: unlit; bottom: in contact with the floor
        // Nudged into the side face: up, and towards the face's centre along it.
        DVec3 p(cube.positions[v]);
        p.y = std::clamp(p.y, kNudge, 1.0 - kNudge);
        const DVec3 along = glm::cross(n, DVec3(0, 1, 0));
        p -= kNudge * (glm::dot(p, along) > 0 ? along : -along);
        const double expected = pointPolygonFormFactor(p, n, floor, {0, 1, 0});
        CAPTURE(cube.positions[v].x);
        CAPTURE(cube.positions[v].y);
        CAPTURE(cube.positions[v].z);
        CHECK(std::abs(values[v].x / expected - 1.0) < 0.02);
        (cube.positions[v].y < 0.5f ? bottom_edge : sides).add(values[v].x, expected);
        if (cube.positions[v].y < 0.5f) CHECK(std::abs(expected - 0.5) < 0.015);
    }
    CHECK(bottom_edge.count == 8);
    ErrorTally near;
    for (size_t i = 0; i < probes.size(); ++i) {
        const double expected = kPi * pointPolygonFormFactor(probes[i].position, probes[i].normal, floor, {0, 1, 0});
        CAPTURE(probes[i].position);
        CHECK(std::abs(baked.probe_irradiance[i].x / expected - 1.0) < 0.02);
        near.add(baked.probe_irradiance[i].x, expected);
    }
    MESSAGE("block on floor: worst bottom-edge vertex " << bottom_edge.worst << ", top edge " << sides.worst
                                                        << ", worst probe 1 mm up " << near.worst);
}

// A closed furnace (every face emitting radiance 1, reflectance rho, each face a grid of quads):
// H = pi L / (1 - rho) everywhere, so H / pi = 1 / (1 - rho) at every vertex, on its edges and
// corners too, and at probes on edges and in corners.
TEST_CASE("a furnace's edges and corners: H = pi L / (1 - rho) at every vertex and at edge and corner probes") {
    // With the edge correction too (reconstruct.cpp): where the radiosity is uniform it must
    // change nothing, whatever each face beside a corner reads there.
    for (const EdgeCorrection edge_correction : {EdgeCorrection::Off, EdgeCorrection::Shared, EdgeCorrection::On})
    for (const double rho : {0.5, 0.9}) {
        CAPTURE(rho);
        CAPTURE(static_cast<int>(edge_correction));
        TempDir dir;
        std::ostringstream material;
        material << "diffuseColor " << rho << ' ' << rho << ' ' << rho << " emissiveColor 1 1 1";
        const std::string m = material.str();
        // Six faces of the unit cube, each facing in.
        const std::string scene = "#VRML V2.0 utf8\n" + gridShape(m, {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 4) +  // y = 0, +y
                                  gridShape(m, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, 4) +                      // y = 1, -y
                                  gridShape(m, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 4) +                      // x = 0, +x
                                  gridShape(m, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 4) +                      // x = 1, -x
                                  gridShape(m, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 4) +                      // z = 0, +z
                                  gridShape(m, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, 4);                       // z = 1, -z
        const std::string path = testfs::writeText(dir, "furnace.wrl", scene);
        const std::vector<Probe> probes = {probeAt({0, 0, 0}, glm::normalize(DVec3(1, 1, 1))),  // a corner
                                           probeAt({0.5, 0, 0}, glm::normalize(DVec3(0, 1, 1))),  // an edge
                                           probeAt({0, 0.3, 1}, glm::normalize(DVec3(1, 0, -1))),
                                           probeAt({1e-3, 0.5, 0.5}, {1, 0, 0})};
        const Bake baked = bakeFile(path, probes, edge_correction);
        const double expected = 1.0 / (1.0 - rho);
        ErrorTally corners, rest;
        for (size_t mesh = 0; mesh < 6; ++mesh) {
            const Mesh& face = baked.scene->meshes[mesh];
            for (size_t v = 0; v < face.positions.size(); ++v) {
                const Vec3 p = face.positions[v];
                const int on_edges = (p.x == 0.0f || p.x == 1.0f) + (p.y == 0.0f || p.y == 1.0f) + (p.z == 0.0f || p.z == 1.0f);
                CAPTURE(p);
                CHECK(std::abs(baked.vertices.values[mesh][v].x / expected - 1.0) < 0.02);
                (on_edges == 3 ? corners : rest).add(baked.vertices.values[mesh][v].x, expected);
            }
        }
        CHECK(corners.count == 24);
        ErrorTally at_probes;
        for (size_t i = 0; i < probes.size(); ++i) {
            CAPTURE(probes[i].position);
            CHECK(std::abs(baked.probe_irradiance[i].x / (kPi * expected) - 1.0) < 0.02);
            at_probes.add(baked.probe_irradiance[i].x, kPi * expected);
        }
        MESSAGE("furnace rho " << rho << std::string(edge_correction == EdgeCorrection::Off ? "" : edge_correction == EdgeCorrection::Shared ? " (edge correction at shared vertices)" : " (edge correction)") << ": worst corner vertex " << corners.worst << ", other vertices " << rest.worst
                               << ", probes " << at_probes.worst);
    }
}

// EdgeCorrection::Shared (medium's default) corrects an output vertex only for the faces beside
// that have vertices at the same point, from the vertex bake's own read there; On reads every
// face beside through its links. In a room whose walls' grids meet on every edge, every face
// beside has a vertex there: the two must agree at every vertex, and both must move the corners
// (a concave corner darkens towards its edges; Off reads it bright).
TEST_CASE("the edge correction at shared vertices equals the full one where every face beside has a vertex") {
    TempDir dir;
    const std::string path = testfs::writeText(dir, "room.wrl", tiledRoom());
    const Bake off = bakeFile(path, std::nullopt, EdgeCorrection::Off);
    const Bake shared = bakeFile(path, std::nullopt, EdgeCorrection::Shared);
    const Bake on = bakeFile(path, std::nullopt, EdgeCorrection::On);
    double corner_change = 0.0;
    size_t corners = 0, moved = 0;
    for (size_t mesh = 0; mesh < 6; ++mesh) {
        const Mesh& face = shared.scene->meshes[mesh];
        for (size_t v = 0; v < face.positions.size(); ++v) {
            const Vec3 p = face.positions[v];
            CAPTURE(p);
            const double s = shared.vertices.values[mesh][v].x, o = on.vertices.values[mesh][v].x,
                         f = off.vertices.values[mesh][v].x;
            REQUIRE(f > 0.0);
            CHECK(s == doctest::Approx(o).epsilon(1e-6));
            const int on_edges = (p.x == 0.0f || p.x == 1.0f) + (p.y == 0.0f || p.y == 1.0f) + (p.z == 0.0f || p.z == 1.0f);
            if (on_edges == 1) CHECK(s == doctest::Approx(f).epsilon(1e-9));  // inside a wall: nothing beside
            moved += std::abs(s / f - 1.0) > 1e-3;
            if (on_edges == 3) {
                ++corners;
                corner_change += s / f - 1.0;
            }
        }
    }
    REQUIRE(corners == 24);
    MESSAGE("corners: mean change " << corner_change / corners << ", vertices moved " << moved);
    CHECK(corner_change / corners < -0.01);  // darker, by more than 1 % on average
}

// The tessellated Cornell box's room (walls 16 x 16 tiles, its 4 x 4 lamp) with its two blocks
// (VRML Boxes) standing on the floor, whose feet cross the floor's tiles: the floor's vertices
// against the exhaustive gather at the same points. Read through the links of the first tile
// around each, they were at 5.0 % rms and 57 % worst; where the tiles' leaves were lit very
// unequally they take the mean through each (vertex_bake.cpp): 3.4 % and 25 %. Not yet the 2 %
// the reconstruction holds inside faces (issue 13's note, session 7).
TEST_CASE("floor vertices where blocks' feet cross its tiles read near the exhaustive gather") {
    TempDir dir;
    const std::string white = "diffuseColor 0.75 0.75 0.75";
    const std::string scene =
        "#VRML V2.0 utf8\n" + gridShape(white, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, 16) +  // floor, +y
        gridShape(white, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, 16) +                           // ceiling, -y
        gridShape(white, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 16) +                           // z = 0, +z
        gridShape(white, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, 16) +                           // z = 1, -z
        gridShape("diffuseColor 0.75 0.15 0.15", {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 16) +   // x = 0, +x
        gridShape("diffuseColor 0.15 0.75 0.15", {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 16) +   // x = 1, -x
        gridShape("diffuseColor 0 0 0 emissiveColor 10 10 10", {0.4, 0.99, 0.4}, {0.2, 0, 0}, {0, 0, 0.2}, 4) +
        "Transform { translation 0.337 0.3 0.372 rotation 0 1 0 0.296706 children Shape {\n"
        " appearance Appearance { material Material { " + white + " } } geometry Box { size 0.3 0.6 0.3 } } }\n"
        "Transform { translation 0.666 0.15 0.698 rotation 0 1 0 -0.296706 children Shape {\n"
        " appearance Appearance { material Material { " + white + " } } geometry Box { size 0.3 0.3 0.3 } } }\n";
    const Bake baked = bakeFile(testfs::writeText(dir, "tessellated_box.wrl", scene));
    const Mesh& floor = baked.scene->meshes[0];
    const std::vector<Vec3>& values = baked.vertices.values[0];
    ErrorTally vertices;
    for (size_t v = 0; v < floor.positions.size(); ++v) {
        const DVec3 p(floor.positions[v]);
        const double expected =
            probeIrradiance(*baked.solution, ReadoutOptions::forQuality(baked.solution->options.quality), p, {0, 1, 0},
                            0)
                .x /
            kPi;
        if (!(expected > 0.01)) continue;  // under a block
        vertices.add(values[v].x, expected);
    }
    CHECK(vertices.count > 200);
    CHECK(vertices.rms() < 0.04);
    CHECK(vertices.worst < 0.35);
    MESSAGE("floor vertices against the exhaustive gather: worst " << vertices.worst << ", rms " << vertices.rms()
                                                                   << " of " << vertices.count);
}

// The ceiling above a lamp hung 1 cm under it, at draft, lit only through the gap: the tiles
// around a vertex near the lamp's edge reach past its shadow unequally, and the vertex read
// through the mean of its tiles' links took up to 1.5 x its light (the tessellated Cornell box's
// worst vertex at draft, +110 %). Vertices whose tiles the solve lit very unequally take the
// exhaustive gather. Against the solution read with exact visibility (100k rays a vertex). The
// vertex over the lamp's centre, its four tiles equally dark, still reads +80 % through its links.
TEST_CASE("at draft, ceiling vertices over a lamp hung just under it read near exact visibility") {
    TempDir dir;
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.lightmaps.enabled = false;
    options.threading.threads = 2;
    Progress progress(false);
    Diagnostics diagnostics;
    const Bake baked = bake(testfs::writeText(dir, "gap.wrl", tiledRoom(16, 0.99)), options, progress, diagnostics);
    REQUIRE(std::string(toString(baked.status)) == "ok");
    const Mesh& ceiling = baked.scene->meshes[1];
    const std::vector<Vec3>& values = baked.vertices.values[1];
    const Solution& s = *baked.solution;
    ParallelRunner runner(Threading{.threads = 1});
    const LinkReconstruction links(s, ReadoutOptions::forQuality(Quality::Draft), runner);
    ErrorTally shadowed;  // over the lamp, but for its centre
    for (size_t v = 0; v < ceiling.positions.size(); ++v) {
        const DVec3 p(ceiling.positions[v]);
        if (p.x < 0.4 || p.x > 0.6 || p.z < 0.4 || p.z > 0.6 || (p.x == 0.5 && p.z == 0.5)) continue;
        const double expected = ceilingGather(s, links, p, 100000, 1 + v) / kPi;
        REQUIRE(expected > 0.0);
        shadowed.add(values[v].x, expected);
    }
    MESSAGE("ceiling vertices over the lamp against exact visibility: worst " << shadowed.worst << ", rms "
                                                                              << shadowed.rms() << " of "
                                                                              << shadowed.count);
    CHECK(shadowed.count == 8);
    CHECK(shadowed.worst < 0.2);  // 0.48 with the mean over the tiles
}

// A block standing on a lit floor, lightmapped at 64 texels/m (1.6 cm texels): floor texels
// whose point lies under the block are hidden (dilated from their lit neighbours), the rest
// are evaluated, against the footprint's geometry; and the lightmap looked up at lit floor
// vertices beside the block's foot (where bilinear lookup reaches texels under the block)
// agrees with the exhaustive gather there.
TEST_CASE("lightmap texels under a block standing on the floor are hidden and do not darken the lit floor beside it") {
    TempDir dir;
    const double angle = 0.3, half = 0.15;
    const DVec2 centre(0.5, 0.5);
    const std::string scene =
        "#VRML V2.0 utf8\n" + gridShape("diffuseColor 0.75 0.75 0.75", {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, 32) +
        gridShape("diffuseColor 0 0 0 emissiveColor 1 1 1", {-0.5, 1, -0.5}, {2, 0, 0}, {0, 0, 2}, 4) +
        "Transform { translation 0.5 0.15 0.5 rotation 0 1 0 " + std::to_string(angle) + " children Shape {\n"
        " appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 } } geometry Box { size 0.3 0.3 0.3 } } }\n";
    BakeOptions options = BakeOptions::forQuality(Quality::Medium);
    options.lightmaps.texels_per_unit = 64.0;
    options.threading.threads = 2;
    Progress progress(false);
    Diagnostics diagnostics;
    const Bake baked = bake(testfs::writeText(dir, "block_on_floor.wrl", scene), options, progress, diagnostics);
    REQUIRE(std::string(toString(baked.status)) == "ok");
    REQUIRE(baked.lightmaps);
    const Lightmaps& lightmaps = baked.lightmaps->lightmaps;
    // Signed distance outside the block's footprint (negative inside), in the floor's x-z plane.
    const auto outside = [&](const DVec3& p) {
        const DVec2 d(p.x - centre.x, p.z - centre.y);
        // VRML rotation about +y by angle: the box's local x axis is (cos, -sin) in x-z.
        const DVec2 local(std::cos(angle) * d.x - std::sin(angle) * d.y, std::sin(angle) * d.x + std::cos(angle) * d.y);
        return std::max(std::abs(local.x), std::abs(local.y)) - half;
    };
    const double texel = 1.0 / 64.0;
    size_t under = 0, hidden_under = 0, lit = 0, hidden_lit = 0;
    for (const LightmapChart& chart : lightmaps.layout.charts) {
        if (chart.mesh != 0) continue;  // the floor
        const LightmapImage& image = lightmaps.images[chart.atlas];
        for (int j = 0; j < chart.height; ++j)
            for (int i = 0; i < chart.width; ++i) {
                DVec2 p_plane;
                size_t face = 0;
                if (!texelSamplePoint(chart, i, j, p_plane, face)) continue;
                const double d = outside(chart.faces[face].worldPoint(p_plane));
                const bool hidden =
                    image.state[static_cast<size_t>(chart.y + j) * image.width + chart.x + i] == TexelState::Dilated;
                if (d < -1e-3) under += 1, hidden_under += hidden;
                if (d > 1e-3) lit += 1, hidden_lit += hidden;
            }
    }
    CHECK(under > 300);  // 0.09 m^2 at 64 texels/m: about 370
    CHECK(hidden_under == under);
    CHECK(hidden_lit == 0);
    CHECK(lightmaps.hidden_texels >= under);
    CHECK(lightmaps.hidden_texels <= under + 4 * 0.3 * 64 + 4);  // at most the texels the footprint's outline crosses

    const LightmapMesh uv_mesh = lightmapMeshes(*baked.scene, lightmaps.layout)[0];
    ErrorTally beside;
    for (size_t v = 0; v < uv_mesh.positions.size(); ++v) {
        const DVec3 p(uv_mesh.positions[v]);
        const double d = outside(p);
        if (d < 0.2 * texel || d > 2.0 * texel) continue;
        const LightmapImage& image = lightmaps.images[uv_mesh.atlas[v]];
        const DVec2 at(uv_mesh.uv[v].x * image.width, uv_mesh.uv[v].y * image.height);
        const double expected =
            probeIrradiance(*baked.solution, ReadoutOptions::forQuality(baked.solution->options.quality), p, {0, 1, 0},
                            0)
                .x /
            kPi;
        beside.add(bilinearLookup(image, at).x, expected);
    }
    CHECK(beside.count >= 8);
    CHECK(beside.worst < 0.08);
    MESSAGE("lightmap beside the block's foot against the exhaustive gather: worst " << beside.worst << ", rms "
                                                                                     << beside.rms() << " of " << beside.count);
}

// The room's 24 corner vertices (8 corners, 3 faces each) against the Monte Carlo reference at
// the vertex nudged into its own face (32768 paths: at most 1 % noise), as output vertices and
// as the lightmap (64 texels/m) looked up there. A corner darkens each of its three faces, and
// each face's light there reads the two others. Before session 11 the vertices read +6.3 % on
// average (worst +11 %): each face corrected from the others' uncorrected light in one step,
// the pieces beside the point read at their centres, and their form factors taken from off two
// of the corner's three planes (reconstruct.cpp, vertex_bake.cpp). Texels were not corrected at
// the default quality (EdgeCorrection::Off's texels, below: +11 %), and once they were, +6.3 %
// until a texel's faces were corrected together as the vertex bake's are.
TEST_CASE("a room's corner vertices and lightmap against the Monte Carlo reference") {
    TempDir dir;
    const std::string path = testfs::writeText(dir, "room.wrl", tiledRoom());
    const auto lightmapped = [&](EdgeCorrection edge_correction) {
        BakeOptions options = BakeOptions::forQuality(Quality::Medium);
        options.readout.edge_correction = edge_correction;
        options.lightmaps.texels_per_unit = 64.0;
        options.threading.threads = 2;
        Progress progress(false);
        Diagnostics diagnostics;
        Bake baked = bake(path, options, progress, diagnostics);
        REQUIRE(std::string(toString(baked.status)) == "ok");
        REQUIRE(baked.lightmaps);
        return baked;
    };
    const Bake baked = lightmapped(ReadoutOptions{}.edge_correction), uncorrected = lightmapped(EdgeCorrection::Off);
    // The lightmap of `b` at mesh m's point p, bilinear as an engine samples it.
    const auto lookup = [](const Bake& b, size_t m, const DVec3& p) {
        const LightmapMesh uv_mesh = lightmapMeshes(*b.scene, b.lightmaps->lightmaps.layout)[m];
        for (size_t v = 0; v < uv_mesh.positions.size(); ++v)
            if (DVec3(uv_mesh.positions[v]) == p) {
                const LightmapImage& image = b.lightmaps->lightmaps.images[uv_mesh.atlas[v]];
                return kPi * bilinearLookup(image, DVec2(uv_mesh.uv[v].x * image.width, uv_mesh.uv[v].y * image.height)).x;
            }
        FAIL("no lightmap vertex at the corner");
        return 0.0;
    };
    std::vector<reference::McProbe> probes;
    std::vector<double> baked_h, texel_h, uncorrected_texel_h;
    for (size_t mesh = 0; mesh < 6; ++mesh) {
        const Mesh& face = baked.scene->meshes[mesh];
        DVec3 lo(face.positions[0]), hi(face.positions[0]);
        for (const Vec3& q : face.positions) {
            lo = glm::min(lo, DVec3(q));
            hi = glm::max(hi, DVec3(q));
        }
        const UVec3& t = face.triangles[0];
        const DVec3 normal = glm::normalize(glm::cross(DVec3(face.positions[t.y] - face.positions[t.x]),
                                                       DVec3(face.positions[t.z] - face.positions[t.x])));
        for (size_t v = 0; v < face.positions.size(); ++v) {
            const DVec3 p(face.positions[v]);
            const int on_edges = (p.x == 0.0 || p.x == 1.0) + (p.y == 0.0 || p.y == 1.0) + (p.z == 0.0 || p.z == 1.0);
            if (on_edges != 3) continue;
            probes.push_back({nudgeInto(p, lo, hi), normal});
            baked_h.push_back(kPi * baked.vertices.values[mesh][v].x);
            texel_h.push_back(lookup(baked, mesh, p));
            uncorrected_texel_h.push_back(lookup(uncorrected, mesh, p));
        }
    }
    REQUIRE(probes.size() == 24);
    reference::McOptions mc;
    mc.samples = 32768;
    mc.threads = 2;
    const std::vector<reference::McProbeResult> expected =
        reference::estimateProbes(reference::McBvh(*baked.scene), probes, mc);
    ErrorTally corners, texels, uncorrected_texels;
    double bias = 0.0, texel_bias = 0.0, uncorrected_texel_bias = 0.0;
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(probes[i].position);
        const double mean = expected[i].irradiance.x;
        REQUIRE(mean > 0.0);
        CHECK(expected[i].standard_error.x < 0.015 * mean);
        corners.add(baked_h[i], mean);
        texels.add(texel_h[i], mean);
        uncorrected_texels.add(uncorrected_texel_h[i], mean);
        bias += (baked_h[i] / mean - 1.0) / double(probes.size());
        texel_bias += (texel_h[i] / mean - 1.0) / double(probes.size());
        uncorrected_texel_bias += (uncorrected_texel_h[i] / mean - 1.0) / double(probes.size());
    }
    MESSAGE("corner vertices against the reference: bias " << bias << ", rms " << corners.rms() << ", worst "
                                                           << corners.worst);
    MESSAGE("the lightmap there: bias " << texel_bias << ", rms " << texels.rms() << ", worst " << texels.worst
                                        << "; texels uncorrected: bias " << uncorrected_texel_bias << ", worst "
                                        << uncorrected_texels.worst);
    CHECK(std::abs(bias) < 0.015);
    CHECK(corners.worst < 0.05);
    CHECK(std::abs(texel_bias) < 0.015);
    CHECK(texels.worst < 0.05);
    CHECK(uncorrected_texel_bias > 0.05);  // what the correction is for
}

// The ceiling above a lamp hung 1 cm under it sees only the walls' tops, through the gap, where
// the lamp hides the lower part of each wall tile, which the ceiling's cosine weights most.
// Against the same solution read with exact visibility (cosine-distributed rays, each bringing
// the radiosity of the leaf it meets): with ReadoutOptions::probe_corner_rays (high, reference)
// or probe_grazing_corner_rays (medium) the read-out is within a few percent; with neither
// +10 % (+14 % on the tessellated Cornell box).
TEST_CASE("the ceiling above a lamp 1 cm under it, read through the gap") {
    TempDir dir;
    const std::string path = testfs::writeText(dir, "gap.wrl", tiledRoom(16, 0.99));
    enum class Corners { None, Grazing, All };
    for (const Corners corners : {Corners::None, Corners::Grazing, Corners::All}) {
        const int corner_rays = static_cast<int>(corners);
        CAPTURE(corner_rays);
        BakeOptions options = BakeOptions::forQuality(Quality::Medium);
        options.readout.probe_corner_rays = corners == Corners::All;
        options.readout.probe_grazing_corner_rays = corners == Corners::Grazing;
        options.lightmaps.enabled = false;
        options.threading.threads = 2;
        const std::vector<DVec3> points = {{0.5625, 1, 0.5}, {0.4375, 1, 0.4375}, {0.5, 1, 0.5625}};
        std::vector<Probe> probes;
        for (const DVec3& p : points) probes.push_back(probeAt(p, {0, -1, 0}));
        options.probes = probes;
        Progress progress(false);
        Diagnostics diagnostics;
        const Bake baked = bake(path, options, progress, diagnostics);
        REQUIRE(std::string(toString(baked.status)) == "ok");
        const Solution& s = *baked.solution;
        ParallelRunner runner(Threading{.threads = 1});
        const LinkReconstruction links(s, ReadoutOptions::forQuality(s.options.quality), runner);
        ErrorTally tally;
        for (size_t i = 0; i < points.size(); ++i) {
            const double exact = ceilingGather(s, links, points[i], 400000, 1 + i);
            REQUIRE(exact > 0.0);
            tally.add(baked.probe_irradiance[i].x, exact);
            MESSAGE("corner rays " << corner_rays << ": probe " << baked.probe_irradiance[i].x << ", exact visibility "
                                   << exact);
        }
        if (corners != Corners::None) CHECK(tally.worst < 0.04);
        else CHECK(tally.worst > 0.05);  // what the corner rays are for
    }
}

// A block standing on a lit floor (the tessellated Cornell box's tall block, a VRML Box, in a
// white room under a lamp): the output vertices at its bottom corners, with the edge
// correction on every face beside (EdgeCorrection::On), against the Monte Carlo reference at
// each vertex nudged into its own face. The floor beside a convex corner is lit differently on
// the way in along each face, so the floor is read where the vertex's own limit comes from (a
// few lifts into its face and off it); read at the corner itself, off every plane there, the
// tessellated box's block corners went from -20 % (uncorrected) to +24 %. And at the corner
// the floor's light turns with the direction (a shadow wedge starts there), so it is read in
// sectors around the corner, and a floor piece cut around the corner counts as beside the
// face wherever part of it is in front (by its centroid, behind, it was left uncorrected).
TEST_CASE("a block's bottom corners, corrected, against the Monte Carlo reference") {
    TempDir dir;
    const std::string white = "diffuseColor 0.75 0.75 0.75";
    const std::string scene =
        "#VRML V2.0 utf8\n" + gridShape(white, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, 8) +  // floor, +y
        gridShape(white, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, 8) + gridShape(white, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 8) +
        gridShape(white, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, 8) + gridShape(white, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 8) +
        gridShape(white, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 8) +
        gridShape("diffuseColor 0 0 0 emissiveColor 10 10 10", {0.4, 0.99, 0.4}, {0.2, 0, 0}, {0, 0, 0.2}, 1) +
        "Transform { translation 0.337 0.3 0.372 rotation 0 1 0 0.296706 children Shape {\n"
        " appearance Appearance { material Material { " + white + " } } geometry Box { size 0.3 0.6 0.3 } } }\n";
    const Bake baked = bakeFile(testfs::writeText(dir, "block.wrl", scene), std::nullopt, EdgeCorrection::On);
    const Mesh& block = baked.scene->meshes[7];
    std::vector<reference::McProbe> probes;
    std::vector<double> baked_h;
    for (size_t t = 0; t < block.triangles.size(); ++t) {
        const UVec3& tri = block.triangles[t];
        const DVec3 a(block.positions[tri.x]), b(block.positions[tri.y]), c(block.positions[tri.z]);
        const DVec3 normal = glm::normalize(glm::cross(b - a, c - a));
        if (std::abs(normal.y) > 0.5) continue;  // the top
        for (const uint32_t v : {tri.x, tri.y, tri.z}) {
            const DVec3 p(block.positions[v]);
            if (p.y > 1e-6) continue;
            // The nudge into the face, as tools/vertex_probes makes it: towards the triangle's centroid.
            const DVec3 to = (a + b + c) / 3.0 - p;
            probes.push_back({p + kNudge * glm::normalize(to), normal});
            baked_h.push_back(kPi * baked.vertices.values[7][v].x);
        }
    }
    REQUIRE(probes.size() >= 8);
    reference::McOptions mc;
    mc.samples = 32768;
    mc.threads = 2;
    const std::vector<reference::McProbeResult> expected =
        reference::estimateProbes(reference::McBvh(*baked.scene), probes, mc);
    ErrorTally corners;
    for (size_t i = 0; i < probes.size(); ++i) {
        CAPTURE(probes[i].position);
        const double mean = expected[i].irradiance.x;
        REQUIRE(mean > 0.0);
        corners.add(baked_h[i], mean);
    }
    MESSAGE("block corners against the reference: rms " << corners.rms() << ", worst " << corners.worst);
    // Read at the corner itself: 7.6 %, worst 14 %; one read on the way in: 4.9 %, worst 10.6 %;
    // in sectors: 1.9 %, worst 4.7 %.
    CHECK(corners.rms() < 0.03);
    CHECK(corners.worst < 0.07);
}

