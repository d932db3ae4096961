#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <thread>

#include "visibility/ray_caster.h"

using namespace radbake;

namespace {

using Quad = std::array<DVec3, 4>;

// Axis-aligned rectangle in the plane z = height, [x0, x1] x [y0, y1], counter-clockwise from +z.
Quad rectangleZ(double x0, double x1, double y0, double y1, double height) {
    return {DVec3(x0, y0, height), DVec3(x1, y0, height), DVec3(x1, y1, height), DVec3(x0, y1, height)};
}

Quad scaled(const Quad& quad, double scale) {
    Quad out;
    for (size_t i = 0; i < 4; ++i) out[i] = quad[i] * scale;
    return out;
}

// One mesh per quad, each quad one polygon of two triangles.
Scene sceneOf(std::initializer_list<Quad> quads) {
    Scene scene;
    scene.materials.push_back({});
    for (const Quad& quad : quads) {
        Mesh mesh;
        for (const DVec3& p : quad) mesh.positions.push_back(Vec3(p));
        mesh.triangles = {UVec3(0, 1, 2), UVec3(0, 2, 3)};
        mesh.triangle_polygon = {0, 0};
        mesh.polygon_count = 1;
        scene.meshes.push_back(std::move(mesh));
    }
    return scene;
}

std::unique_ptr<RayCaster> buildOrFail(const Scene& scene) {
    Diagnostics diagnostics;
    auto caster = RayCaster::build(scene, diagnostics);
    REQUIRE(caster != nullptr);
    REQUIRE(diagnostics.errorCount() == 0);
    return caster;
}

const Quad kSource = rectangleZ(0, 1, 0, 1, 0);
const Quad kReceiver = rectangleZ(0, 1, 0, 1, 1);
// Just in front of the receiver, covering its x < 0.5 half: the edge lies between sample
// strata (x = 0.375 and 0.625 for n = 4), and at 0.01 from the receiver a segment's x there
// differs from its receiver end by at most 0.01, so exactly the segments that reach the
// covered half are blocked.
const Quad kHalfWall = rectangleZ(-1, 0.5, -1, 2, 0.99);
// Halfway, covering x < 0.51: blocks the segments whose midpoint has x < 0.51, half of all
// point pairs (plus 1 %) by symmetry. The edge is off 0.5 so that no sample segment grazes it.
const Quad kMidWall = rectangleZ(-1, 0.51, -1, 2, 0.5);

}  // namespace

TEST_CASE("two facing squares with nothing between see each other fully") {
    const Scene scene = sceneOf({kSource, kReceiver});
    auto caster = buildOrFail(scene);
    CHECK(caster->triangleCount() == 4);
    CHECK(caster->sceneExtent() == doctest::Approx(std::sqrt(3.0)).epsilon(1e-12));
    CHECK(caster->epsilon() == doctest::Approx(1e-5 * std::sqrt(3.0)).epsilon(1e-12));
    size_t rays = 0;
    for (int n : {1, 2, 4, 7}) CHECK(caster->visibleFraction(kSource, kReceiver, n, &rays) == 1.0);
    CHECK(rays == 1 + 4 + 16 + 49);
}

TEST_CASE("a wall fully between two squares blocks every segment") {
    const Scene scene = sceneOf({kSource, kReceiver, rectangleZ(-1, 2, -1, 2, 0.5)});
    auto caster = buildOrFail(scene);
    for (int n : {1, 3, 4, 8}) CHECK(caster->visibleFraction(kSource, kReceiver, n) == 0.0);
    // A wall behind the receiver does not block.
    const Scene behind = sceneOf({kSource, kReceiver, rectangleZ(-1, 2, -1, 2, 1.5)});
    CHECK(buildOrFail(behind)->visibleFraction(kSource, kReceiver, 4) == 1.0);
}

TEST_CASE("a wall covering half the receiver gives one half") {
    const Scene scene = sceneOf({kSource, kReceiver, kHalfWall});
    auto caster = buildOrFail(scene);
    CHECK(caster->visibleFraction(kSource, kReceiver, 4) == 0.5);
    CHECK(caster->visibleFraction(kSource, kReceiver, 8) == 0.5);

    // Halfway between, the true fraction is 0.49 (strip 0.5 < x_mid < 0.51 blocked: 1 %); the
    // pairs' (x_s, x_r) form a full n x n grid, whose diagonal of n cells sits on the edge:
    // the estimate errs by about 1/(2n), within 1/n.
    const Scene mid = sceneOf({kSource, kReceiver, kMidWall});
    auto mid_caster = buildOrFail(mid);
    for (int n : {4, 5, 8, 16}) CHECK(std::abs(mid_caster->visibleFraction(kSource, kReceiver, n) - 0.49) <= 1.0 / n);
}

TEST_CASE("answers are repeatable and identical from two threads at once") {
    const Scene scene = sceneOf({kSource, kReceiver, kMidWall, rectangleZ(0.3, 0.9, 0.2, 0.6, 0.3)});
    auto caster = buildOrFail(scene);
    // Receivers sliding across, so the answers vary.
    std::vector<Quad> receivers;
    for (int i = 0; i < 64; ++i) {
        const double shift = -1.0 + i / 32.0;
        receivers.push_back(rectangleZ(shift, shift + 1, 0.1 * i / 64.0, 1, 1));
    }
    auto evaluate = [&](std::vector<double>& out) {
        out.clear();
        for (const Quad& receiver : receivers) out.push_back(caster->visibleFraction(kSource, receiver, 6));
    };
    std::vector<double> reference, again, first, second;
    evaluate(reference);
    evaluate(again);
    CHECK(reference == again);
    std::thread a([&] { evaluate(first); });
    std::thread b([&] { evaluate(second); });
    a.join();
    b.join();
    CHECK(first == reference);
    CHECK(second == reference);
    // A structure built on one thread answers the same.
    Diagnostics diagnostics;
    auto single = RayCaster::build(scene, diagnostics, 1);
    REQUIRE(single != nullptr);
    std::vector<double> from_single;
    for (const Quad& receiver : receivers) from_single.push_back(single->visibleFraction(kSource, receiver, 6));
    CHECK(from_single == reference);
    // The set is not trivial: both extremes and something between occur.
    std::vector<double> distinct = reference;
    std::sort(distinct.begin(), distinct.end());
    CHECK(std::unique(distinct.begin(), distinct.end()) - distinct.begin() >= 10);
}

TEST_CASE("a segment ending or starting exactly on a surface is not blocked by it") {
    const Scene scene = sceneOf({kSource, kReceiver});
    auto caster = buildOrFail(scene);
    const DVec3 on_receiver(0.5, 0.5, 1.0), on_source(0.3, 0.7, 0.0);
    CHECK_FALSE(caster->segmentBlocked(DVec3(0.5, 0.5, 0.5), on_receiver));
    CHECK_FALSE(caster->segmentBlocked(on_receiver, DVec3(0.5, 0.5, 0.5)));
    CHECK_FALSE(caster->segmentBlocked(on_source, on_receiver));
    CHECK_FALSE(caster->segmentBlocked(on_receiver, on_source));
    // On the receiver's shared diagonal (an edge between its two triangles) too.
    CHECK_FALSE(caster->segmentBlocked(DVec3(0.2, 0.3, 0.5), DVec3(0.25, 0.25, 1.0)));
    // The same surfaces do block segments that cross them.
    CHECK(caster->segmentBlocked(DVec3(0.5, 0.5, 0.5), DVec3(0.5, 0.5, 1.5)));
    CHECK(caster->segmentBlocked(DVec3(0.5, 0.5, -0.5), on_receiver));
    // Crossing through the shared diagonal and a vertex: robust traversal finds them.
    CHECK(caster->segmentBlocked(DVec3(0.5, 0.5, 0.5), DVec3(0.5, 0.5, -0.5)));
    CHECK(caster->segmentBlocked(DVec3(0.25, 0.25, 0.5), DVec3(0.25, 0.25, 1.5)));
    // Degenerate segments are never blocked.
    CHECK_FALSE(caster->segmentBlocked(on_receiver, on_receiver));
}

TEST_CASE("scenes scaled by 1e-4 and 1e6 give the same fractions") {
    const Quad tilted = {DVec3(0.2, -0.5, 0.3), DVec3(0.9, -0.5, 0.6), DVec3(0.9, 1.5, 0.6), DVec3(0.2, 1.5, 0.3)};
    auto fractionsAt = [&](double scale) {
        const Scene scene = sceneOf({scaled(kSource, scale), scaled(kReceiver, scale), scaled(kMidWall, scale),
                                     scaled(tilted, scale)});
        auto caster = buildOrFail(scene);
        // Bounds x [-1, 1], y [-1, 2], z [0, 1] (the mid wall is wide): diagonal sqrt(14).
        CHECK(caster->epsilon() == doctest::Approx(1e-5 * std::sqrt(14.0) * scale).epsilon(1e-6));
        std::vector<double> out;
        for (int n : {3, 4, 8}) {
            out.push_back(caster->visibleFraction(scaled(kSource, scale), scaled(kReceiver, scale), n));
            const Quad receiver = scaled(rectangleZ(0.5, 1.5, 0, 1, 1), scale);
            out.push_back(caster->visibleFraction(scaled(kSource, scale), receiver, n));
        }
        return out;
    };
    const std::vector<double> unit = fractionsAt(1.0);
    CHECK(fractionsAt(1e-4) == unit);
    CHECK(fractionsAt(1e6) == unit);
    CHECK(std::count_if(unit.begin(), unit.end(), [](double f) { return f > 0.0 && f < 1.0; }) >= 3);
}

TEST_CASE("a small scene far from the origin keeps its precision") {
    // At 1e5 the float spacing is 1/128: the geometry below is stored exactly (the half wall
    // at 0.99 rounds to 0.9921875, still between the strata), and a world-frame epsilon scaled
    // by the coordinates (~1) would swallow the whole unit-sized scene.
    const DVec3 far(1e5, 1e5, 1e5);
    auto moved = [&](const Quad& quad) {
        Quad out;
        for (size_t i = 0; i < 4; ++i) out[i] = quad[i] + far;
        return out;
    };
    const Quad source = moved(kSource), receiver = moved(kReceiver);
    const Scene open_scene = sceneOf({source, receiver});
    auto open_caster = buildOrFail(open_scene);
    CHECK(open_caster->epsilon() < 1e-4);
    CHECK(open_caster->visibleFraction(source, receiver, 4) == 1.0);
    CHECK_FALSE(open_caster->segmentBlocked(far + DVec3(0.5, 0.5, 0.5), far + DVec3(0.5, 0.5, 1.0)));
    CHECK(open_caster->segmentBlocked(far + DVec3(0.5, 0.5, 0.5), far + DVec3(0.5, 0.5, 1.01)));
    const Scene walled = sceneOf({source, receiver, moved(rectangleZ(-1, 2, -1, 2, 0.5))});
    CHECK(buildOrFail(walled)->visibleFraction(source, receiver, 4) == 0.0);
    const Scene half = sceneOf({source, receiver, moved(kHalfWall)});
    CHECK(buildOrFail(half)->visibleFraction(source, receiver, 4) == 0.5);
}

TEST_CASE("the candidate-list variant matches Embree with all triangles and sees only its candidates") {
    const Scene scene = sceneOf({kSource, kReceiver, kMidWall});
    auto caster = buildOrFail(scene);
    std::vector<TriangleRef> all;
    for (uint32_t m = 0; m < 3; ++m) all.push_back({m, 0}), all.push_back({m, 1});
    for (int n : {2, 4, 8})
        CHECK(caster->visibleFractionAmong(kSource, kReceiver, n, all) == caster->visibleFraction(kSource, kReceiver, n));
    CHECK(caster->visibleFractionAmong(kSource, kReceiver, 4, {}) == 1.0);

    // The wall's part gives exactly its two triangles.
    ConvexPart wall;
    wall.mesh = 2;
    wall.polygons = {0};
    std::vector<TriangleRef> candidates;
    caster->appendPartTriangles(wall, candidates);
    REQUIRE(candidates.size() == 2);
    CHECK(candidates[0].mesh == 2);
    CHECK(candidates[0].triangle == 0);
    CHECK(candidates[1].triangle == 1);
    CHECK(caster->visibleFractionAmong(kSource, kReceiver, 8, candidates) ==
          caster->visibleFraction(kSource, kReceiver, 8));
    // A part naming a polygon that does not exist adds nothing.
    wall.polygons = {5};
    caster->appendPartTriangles(wall, candidates);
    CHECK(candidates.size() == 2);
}

TEST_CASE("packet-cast visibleFraction equals single segments over the same pairs") {
    const Quad tilted = {DVec3(0.2, -0.5, 0.3), DVec3(0.9, -0.5, 0.6), DVec3(0.9, 1.5, 0.6), DVec3(0.2, 1.5, 0.3)};
    const Scene scene = sceneOf({kSource, kReceiver, kMidWall, tilted});
    auto caster = buildOrFail(scene);
    for (int n : {1, 3, 4, 5, 8}) {
        // The pairing is a bijection.
        std::vector<size_t> image;
        for (size_t k = 0; k < size_t(n * n); ++k) image.push_back(pairedSampleIndex(k, n));
        std::sort(image.begin(), image.end());
        for (size_t k = 0; k < image.size(); ++k) CHECK(image[k] == k);
        for (const Quad& receiver : {kReceiver, rectangleZ(0.4, 1.4, -0.3, 0.7, 1.0)}) {
            const auto from = stratifiedPolygonPoints(kSource, n);
            const auto to = stratifiedPolygonPoints(receiver, n);
            size_t open = 0;
            for (size_t k = 0; k < from.size(); ++k) open += !caster->segmentBlocked(from[k], to[pairedSampleIndex(k, n)]);
            CHECK(caster->visibleFraction(kSource, receiver, n) == double(open) / double(n * n));
        }
    }
}

TEST_CASE("Embree agrees with a brute-force double-precision test on random triangles") {
    std::mt19937 random(1234);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Scene scene;
    scene.materials.push_back({});
    Mesh mesh;
    for (uint32_t t = 0; t < 200; ++t) {
        const DVec3 centre(unit(random), unit(random), unit(random));
        for (int k = 0; k < 3; ++k)
            mesh.positions.push_back(Vec3(centre + 0.15 * DVec3(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5)));
        mesh.triangles.push_back(UVec3(3 * t, 3 * t + 1, 3 * t + 2));
        mesh.triangle_polygon.push_back(t);
    }
    mesh.polygon_count = 200;
    scene.meshes.push_back(mesh);
    auto caster = buildOrFail(scene);
    std::vector<TriangleRef> all;
    for (uint32_t t = 0; t < 200; ++t) all.push_back({0, t});
    int disagreements = 0, blocked = 0;
    const int kSegments = 20000;
    for (int i = 0; i < kSegments; ++i) {
        const DVec3 a(unit(random), unit(random), unit(random)), b(unit(random), unit(random), unit(random));
        const bool embree = caster->segmentBlocked(a, b);
        blocked += embree;
        disagreements += embree != caster->segmentBlockedAmong(a, b, all);
    }
    // Float versus double can only differ for segments within float rounding of a triangle's
    // edge or of an end offset: a budget of 1 in 10^4 segments.
    CHECK(disagreements <= kSegments / 10000);
    CHECK(blocked > kSegments / 10);
    CHECK(blocked < kSegments * 9 / 10);
}

TEST_CASE("stratified points lie on the polygon, with the polygon's centroid as mean") {
    const std::vector<DVec3> triangle = {DVec3(0, 0, 0), DVec3(3, 0, 0), DVec3(0, 3, 0)};
    // A regular pentagon of circumradius 1 around (1, 2, 0) in the z = 0 plane.
    std::vector<DVec3> pentagon;
    for (int k = 0; k < 5; ++k)
        pentagon.push_back(DVec3(1 + std::cos(2 * kPi * k / 5), 2 + std::sin(2 * kPi * k / 5), 0));
    const auto tri_points = stratifiedPolygonPoints(triangle, 10);
    const auto penta_points = stratifiedPolygonPoints(pentagon, 10);
    REQUIRE(tri_points.size() == 100);
    REQUIRE(penta_points.size() == 100);
    DVec3 tri_mean(0.0), penta_mean(0.0);
    for (const DVec3& p : tri_points) {
        CHECK(p.z == 0.0);
        CHECK(p.x >= 0.0);
        CHECK(p.y >= 0.0);
        CHECK(p.x + p.y <= 3.0);
        tri_mean += p / 100.0;
    }
    for (const DVec3& p : penta_points) {
        CHECK(glm::length(p - DVec3(1, 2, 0)) <= 1.0 + 1e-12);
        penta_mean += p / 100.0;
    }
    // Equal-area strata: the mean converges to the centroid at O(1/n) (0.1 of the size here).
    CHECK(glm::length(tri_mean - DVec3(1, 1, 0)) < 0.05);
    CHECK(glm::length(penta_mean - DVec3(1, 2, 0)) < 0.05);
    // A parallelogram's bilinear cell centres average exactly to its centre.
    const auto quad_points = stratifiedPolygonPoints(std::vector<DVec3>{DVec3(0, 0, 0), DVec3(2, 0, 0), DVec3(3, 1, 0), DVec3(1, 1, 0)}, 4);
    DVec3 quad_mean(0.0);
    for (const DVec3& p : quad_points) quad_mean += p / 16.0;
    CHECK(quad_mean.x == doctest::Approx(1.5));
    CHECK(quad_mean.y == doctest::Approx(0.5));
}

TEST_CASE("bad triangles are skipped with a warning, the rest still block") {
    Scene scene = sceneOf({rectangleZ(-1, 2, -1, 2, 0.5)});
    scene.meshes[0].triangles.push_back(UVec3(0, 1, 9));  // index out of range
    scene.meshes[0].triangle_polygon.push_back(0);
    Diagnostics diagnostics;
    auto caster = RayCaster::build(scene, diagnostics);
    REQUIRE(caster != nullptr);
    CHECK(diagnostics.errorCount() == 0);
    REQUIRE(diagnostics.warningCount() == 1);
    CHECK(diagnostics.all()[0].message.find("skipped 1 triangle") != std::string::npos);
    CHECK(caster->triangleCount() == 2);
    CHECK(caster->visibleFraction(kSource, kReceiver, 4) == 0.0);
    CHECK(caster->reportLateErrors(diagnostics) == 0);
}

TEST_CASE("an empty scene blocks nothing") {
    Scene scene;
    auto caster = buildOrFail(scene);
    CHECK(caster->sceneExtent() == 0.0);
    CHECK(caster->triangleCount() == 0);
    CHECK(caster->visibleFraction(kSource, kReceiver, 3) == 1.0);
    CHECK_FALSE(caster->segmentBlocked(DVec3(0.0), DVec3(1.0)));
}

TEST_CASE("ray caster: transmitting surfaces pass their share of light, once per crossing") {
    // Two panes (t 0.5 and 0.6) at z = 1 and z = 2, an opaque plate at z = 3 over x < 0.
    Scene scene = sceneOf({rectangleZ(-2, 2, -2, 2, 1), rectangleZ(-2, 2, -2, 2, 2), rectangleZ(-2, 0, -2, 2, 3)});
    scene.materials.resize(3);
    scene.materials[1].transparency = 0.5f;
    scene.materials[2].transparency = 0.6f;
    scene.meshes[0].material = 1;
    scene.meshes[1].material = 2;
    scene.meshes[2].material = 0;
    const auto caster = buildOrFail(scene);
    CHECK(caster->transmittance({0.5, 0.3, 0.5}, {0.5, 0.3, 1.5}) == doctest::Approx(0.5));
    CHECK(caster->transmittance({0.5, 0.3, 0.5}, {0.7, 0.1, 2.5}) == doctest::Approx(0.3));
    CHECK(caster->transmittance({0.5, 0.3, 0.5}, {0.5, 0.3, 3.5}) == doctest::Approx(0.3));  // beside the plate
    CHECK(caster->transmittance({-0.5, 0.3, 0.5}, {-0.5, 0.3, 3.5}) == 0.0);                // through it
    CHECK(!caster->segmentBlocked({0.5, 0.3, 0.5}, {0.5, 0.3, 2.5}));
    CHECK(caster->segmentBlocked({-0.5, 0.3, 0.5}, {-0.5, 0.3, 3.5}));
    // A segment through the diagonal seam of a pane's two triangles crosses it once.
    CHECK(caster->transmittance({0.25, 0.25, 0.5}, {0.25, 0.25, 1.5}) == doctest::Approx(0.5));
    CHECK(caster->transmittance({-1.0, -1.0, 0.5}, {1.0, 1.0, 1.5}) == doctest::Approx(0.5));
    // The packets agree with the single segments, and the weighted count and the fractions sum
    // transmittances.
    const std::vector<DVec3> to = {{0.5, 0.3, 1.5}, {0.5, 0.3, 2.5}, {-0.5, 0.3, 3.5}, {1.0, 1.0, 0.9},
                                   {0.25, 0.25, 1.5}};
    std::vector<float> through(to.size());
    caster->transmittanceFrom({0.5, 0.3, 0.5}, to, through);
    for (size_t k = 0; k < to.size(); ++k)
        CHECK(through[k] == doctest::Approx(caster->transmittance({0.5, 0.3, 0.5}, to[k])));
    const std::vector<double> weights(to.size(), 1.0);
    double open_weight = 0.0;
    CHECK(caster->countOpenFrom({0.5, 0.3, 0.5}, to, weights, open_weight) == 4);
    CHECK(open_weight == doctest::Approx(0.5 + 0.3 + 0.0 + 1.0 + 0.5).epsilon(1e-6));
    CHECK(caster->visibleFraction(rectangleZ(0.1, 0.9, 0.1, 0.9, 0.5), rectangleZ(0.1, 0.9, 0.1, 0.9, 2.5), 3) ==
          doctest::Approx(0.3).epsilon(1e-6));
}
