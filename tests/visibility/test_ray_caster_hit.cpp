// RayCaster::closestHit against a brute-force double-precision loop over every triangle.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <thread>
#include <vector>

#include "visibility/ray_caster.h"

using namespace radbake;

namespace {

// A randomly rotated, randomly sized box as one mesh of 12 outward-facing triangles.
Mesh randomBox(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const DVec3 centre(-5.0 + 10.0 * unit(rng), -5.0 + 10.0 * unit(rng), -5.0 + 10.0 * unit(rng));
    const DVec3 half(0.2 + 1.5 * unit(rng), 0.2 + 1.5 * unit(rng), 0.2 + 1.5 * unit(rng));
    const glm::dquat rotation = glm::normalize(glm::dquat(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5));
    Mesh mesh;
    for (int k = 0; k < 8; ++k) {
        const DVec3 corner((k & 1) ? half.x : -half.x, (k & 2) ? half.y : -half.y, (k & 4) ? half.z : -half.z);
        mesh.positions.push_back(Vec3(centre + rotation * corner));
    }
    // Faces as quads (corner indices, counter-clockwise from outside), two triangles each.
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (uint32_t f = 0; f < 6; ++f) {
        const int* q = faces[f];
        mesh.triangles.push_back(UVec3(q[0], q[1], q[2]));
        mesh.triangles.push_back(UVec3(q[0], q[2], q[3]));
        mesh.triangle_polygon.push_back(f);
        mesh.triangle_polygon.push_back(f);
    }
    mesh.polygon_count = 6;
    return mesh;
}

struct BruteHit {
    TriangleRef triangle;
    double t = 0.0;
    double edge_margin = 0.0;  // smallest barycentric coordinate (how far from the triangle's edges)
};

// Moller-Trumbore in double; `slack` widens the triangle by that barycentric margin.
std::optional<BruteHit> hitTriangle(const Scene& scene, TriangleRef ref, const DVec3& origin, const DVec3& unit,
                                    double t_min, double t_max, double slack = 0.0) {
    const Mesh& mesh = scene.meshes[ref.mesh];
    const UVec3 tri = mesh.triangles[ref.triangle];
    const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
    const DVec3 e1 = b - a, e2 = c - a;
    const DVec3 p = glm::cross(unit, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) return std::nullopt;
    const DVec3 s = origin - a;
    const double u = glm::dot(s, p) / det;
    const DVec3 q = glm::cross(s, e1);
    const double v = glm::dot(unit, q) / det;
    const double w = 1.0 - u - v;
    if (u < -slack || v < -slack || w < -slack) return std::nullopt;
    const double t = glm::dot(e2, q) / det;
    if (!(t >= t_min && t <= t_max)) return std::nullopt;
    return BruteHit{ref, t, std::min({u, v, w})};
}

std::optional<BruteHit> bruteClosest(const Scene& scene, const DVec3& origin, const DVec3& unit, double t_min,
                                     double t_max) {
    std::optional<BruteHit> best;
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        for (uint32_t t = 0; t < scene.meshes[m].triangles.size(); ++t) {
            const std::optional<BruteHit> hit = hitTriangle(scene, {m, t}, origin, unit, t_min, t_max);
            if (hit && (!best || hit->t < best->t)) best = hit;
        }
    return best;
}

struct Ray {
    DVec3 origin, direction;
    double t_max;
};

// Two rays in three aim near a random box's centre, so most of them hit something.
std::vector<Ray> randomRays(std::mt19937_64& rng, const Scene& scene, size_t count) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::vector<Ray> rays;
    for (size_t i = 0; i < count; ++i) {
        Ray ray;
        ray.origin = DVec3(-9.0 + 18.0 * unit(rng), -9.0 + 18.0 * unit(rng), -9.0 + 18.0 * unit(rng));
        // Not normalised on purpose: closestHit normalises, t is a distance.
        ray.direction = DVec3(normal(rng), normal(rng), normal(rng));
        if (i % 3 != 2) {
            const Mesh& box = scene.meshes[rng() % scene.meshes.size()];
            DVec3 centre(0.0);
            for (const Vec3& p : box.positions) centre += DVec3(p) / double(box.positions.size());
            ray.direction = centre + ray.direction - ray.origin;
        }
        ray.direction *= 0.5 + 3.0 * unit(rng);
        ray.t_max = (i % 3 == 0) ? std::numeric_limits<double>::infinity() : 2.0 + 15.0 * unit(rng);
        rays.push_back(ray);
    }
    return rays;
}

}  // namespace

TEST_CASE("closestHit agrees with a brute-force double-precision loop on random boxes") {
    std::mt19937_64 rng(20261122);
    Scene scene;
    scene.materials.push_back({});
    for (int b = 0; b < 24; ++b) scene.meshes.push_back(randomBox(rng));
    Diagnostics diagnostics;
    auto caster = RayCaster::build(scene, diagnostics);
    REQUIRE(caster != nullptr);
    REQUIRE(caster->triangleCount() == 24u * 12u);
    // Embree works in float in a frame centred on the scene (coordinates up to ~extent / 2):
    // a few float ulps of the extent, 1e-6 x extent, bounds its errors in t and in the hit point.
    const double tolerance = 1e-6 * caster->sceneExtent();
    const double eps = caster->epsilon();

    const std::vector<Ray> rays = randomRays(rng, scene, 1000);
    int hits = 0, same_triangle = 0, edge_ties = 0, boundary_misses = 0;
    for (const Ray& ray : rays) {
        const DVec3 unit = glm::normalize(ray.direction);
        const std::optional<RayHit> got = caster->closestHit(ray.origin, ray.direction, ray.t_max);
        const std::optional<BruteHit> want = bruteClosest(scene, ray.origin, unit, eps, ray.t_max);
        if (got.has_value() != want.has_value()) {
            // Only a hit within float noise of an edge of the scene's silhouette or of a range
            // end may be seen by one side and not the other.
            ++boundary_misses;
            if (want) {
                const bool grazing = want->edge_margin < 1e-5 || want->t > ray.t_max - tolerance || want->t < eps + tolerance;
                CHECK(grazing);
            }
            continue;
        }
        if (!want) continue;
        ++hits;
        CHECK(std::abs(got->t - want->t) <= tolerance);
        if (got->triangle.mesh == want->triangle.mesh && got->triangle.triangle == want->triangle.triangle) {
            ++same_triangle;
        } else {
            // Two triangles sharing the crossed edge (a box face's diagonal): the reported one
            // must also be hit, at the same distance, within float noise of its edge.
            ++edge_ties;
            const std::optional<BruteHit> other =
                hitTriangle(scene, got->triangle, ray.origin, unit, eps - tolerance, ray.t_max + tolerance, 1e-5);
            REQUIRE(other.has_value());
            CHECK(std::abs(other->t - want->t) <= tolerance);
        }
        // (u, v) are the barycentrics of corners 1 and 2: they rebuild the hit point.
        const Mesh& mesh = scene.meshes[got->triangle.mesh];
        const UVec3 tri = mesh.triangles[got->triangle.triangle];
        const DVec3 p_bary = (1.0 - got->u - got->v) * DVec3(mesh.positions[tri.x]) + got->u * DVec3(mesh.positions[tri.y]) +
                             got->v * DVec3(mesh.positions[tri.z]);
        CHECK(glm::length(p_bary - (ray.origin + got->t * unit)) <= 10.0 * tolerance);
    }
    MESSAGE("hits " << hits << ", same triangle " << same_triangle << ", edge ties " << edge_ties
                    << ", boundary disagreements " << boundary_misses);
    // Random rays reach an edge within float noise rarely: a budget of 1 % each.
    CHECK(hits > 300);
    CHECK(edge_ties <= 10);
    CHECK(boundary_misses <= 10);
    CHECK(same_triangle + edge_ties == hits);
}

TEST_CASE("closestHit: ranges, offsets and skipped triangles") {
    // Mesh 0: a unit square in z = 0 (two triangles) preceded by an unusable triangle, so
    // Embree's primitive numbering differs from the mesh's triangle indices.
    Scene scene;
    scene.materials.push_back({});
    Mesh mesh;
    mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    mesh.triangles = {UVec3(0, 1, 99), UVec3(0, 1, 2), UVec3(0, 2, 3)};
    scene.meshes.push_back(mesh);
    Mesh far = mesh;  // the same square at z = -2
    for (Vec3& p : far.positions) p.z = -2.0f;
    far.triangles = {UVec3(0, 1, 2), UVec3(0, 2, 3)};
    scene.meshes.push_back(far);
    Diagnostics diagnostics;
    auto caster = RayCaster::build(scene, diagnostics);
    REQUIRE(caster != nullptr);
    CHECK(diagnostics.warningCount() == 1);

    // Down onto (0.75, 0.25): triangle 1 of mesh 0 (corners 0, 1, 2), u = 0.5, v = 0.25.
    std::optional<RayHit> hit = caster->closestHit(DVec3(0.75, 0.25, 3.0), DVec3(0, 0, -2.0), 100.0);
    REQUIRE(hit.has_value());
    CHECK(hit->triangle.mesh == 0u);
    CHECK(hit->triangle.triangle == 1u);
    CHECK(hit->t == doctest::Approx(3.0).epsilon(1e-6));
    CHECK(hit->u == doctest::Approx(0.5).epsilon(1e-5));
    CHECK(hit->v == doctest::Approx(0.25).epsilon(1e-5));
    // (0.25, 0.75) lies in triangle 2 (corners 0, 2, 3): u = 0.25, v = 0.5.
    hit = caster->closestHit(DVec3(0.25, 0.75, 3.0), DVec3(0, 0, -1.0), 100.0);
    REQUIRE(hit.has_value());
    CHECK(hit->triangle.triangle == 2u);
    CHECK(hit->u == doctest::Approx(0.25).epsilon(1e-5));
    CHECK(hit->v == doctest::Approx(0.5).epsilon(1e-5));

    // t_max short of the surface: a miss; just beyond it: a hit.
    CHECK_FALSE(caster->closestHit(DVec3(0.5, 0.3, 3.0), DVec3(0, 0, -1), 2.99).has_value());
    CHECK(caster->closestHit(DVec3(0.5, 0.3, 3.0), DVec3(0, 0, -1), 3.01).has_value());
    // Leaving a surface from a point on it: that surface is skipped (epsilon offset), the
    // next one is found.
    hit = caster->closestHit(DVec3(0.5, 0.3, 0.0), DVec3(0, 0, -1), 100.0);
    REQUIRE(hit.has_value());
    CHECK(hit->triangle.mesh == 1u);
    CHECK(hit->t == doctest::Approx(2.0).epsilon(1e-6));
    // Back faces count: from below, upwards.
    hit = caster->closestHit(DVec3(0.5, 0.3, -1.0), DVec3(0, 0, 1), 100.0);
    REQUIRE(hit.has_value());
    CHECK(hit->triangle.mesh == 0u);
    CHECK(hit->t == doctest::Approx(1.0).epsilon(1e-6));
    // Degenerate queries.
    CHECK_FALSE(caster->closestHit(DVec3(0.5, 0.3, 3.0), DVec3(0.0), 100.0).has_value());
    CHECK_FALSE(caster->closestHit(DVec3(0.5, 0.3, 3.0), DVec3(0, 0, -1), 0.0).has_value());
    CHECK_FALSE(caster->closestHit(DVec3(2.0, 0.3, 3.0), DVec3(0, 0, -1), 100.0).has_value());
}

TEST_CASE("closestHit gives the same answers on several threads at once") {
    std::mt19937_64 rng(7);
    Scene scene;
    scene.materials.push_back({});
    for (int b = 0; b < 10; ++b) scene.meshes.push_back(randomBox(rng));
    Diagnostics diagnostics;
    auto caster = RayCaster::build(scene, diagnostics, 2);
    REQUIRE(caster != nullptr);
    const std::vector<Ray> rays = randomRays(rng, scene, 400);
    auto run = [&](std::vector<std::optional<RayHit>>& out) {
        out.clear();
        for (const Ray& ray : rays) out.push_back(caster->closestHit(ray.origin, ray.direction, ray.t_max));
    };
    std::vector<std::optional<RayHit>> serial, a, b;
    run(serial);
    std::thread ta([&] { run(a); });
    std::thread tb([&] { run(b); });
    ta.join();
    tb.join();
    size_t hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        for (const auto* other : {&a, &b}) {
            REQUIRE((*other)[i].has_value() == serial[i].has_value());
            if (!serial[i]) continue;
            CHECK((*other)[i]->triangle.mesh == serial[i]->triangle.mesh);
            CHECK((*other)[i]->triangle.triangle == serial[i]->triangle.triangle);
            CHECK((*other)[i]->t == serial[i]->t);
            CHECK((*other)[i]->u == serial[i]->u);
        }
        hits += serial[i].has_value();
    }
    CHECK(hits > 50);
}

TEST_CASE("closestHit on coincident faces names the least triangle, whatever instruction set Embree runs") {
    // Random boxes each doubled by a coincident copy facing inward (a floor slab and the
    // ceiling under it): every hit is a tie between two faces.
    std::mt19937_64 rng(20261206);
    Scene scene;
    for (int b = 0; b < 6; ++b) {
        Mesh outward = randomBox(rng);
        Mesh inward = outward;
        for (UVec3& t : inward.triangles) std::swap(t.y, t.z);
        scene.meshes.push_back(std::move(outward));
        scene.meshes.push_back(std::move(inward));
    }
    std::vector<std::pair<DVec3, DVec3>> rays;
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int k = 0; k < 12000; ++k)
        rays.push_back({DVec3(6 * unit(rng), 6 * unit(rng), 6 * unit(rng)),
                        glm::normalize(DVec3(unit(rng), unit(rng), unit(rng)))});
    std::vector<std::vector<std::optional<RayHit>>> answers;
    for (const char* isa : {"isa=sse4.2", "isa=avx2"}) {
        setenv("RADBAKE_EMBREE_CONFIG", isa, 1);
        Diagnostics diagnostics;
        auto caster = RayCaster::build(scene, diagnostics);
        unsetenv("RADBAKE_EMBREE_CONFIG");
        REQUIRE(caster);
        std::vector<std::optional<RayHit>> hits;
        for (const auto& [origin, direction] : rays) hits.push_back(caster->closestHit(origin, direction, 100.0));
        answers.push_back(std::move(hits));
    }
    size_t hits = 0, least = 0, differing = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
        const auto& a = answers[0][k];
        const auto& b = answers[1][k];
        if (a.has_value() != b.has_value() || (a && (a->triangle.mesh != b->triangle.mesh ||
                                                     a->triangle.triangle != b->triangle.triangle ||
                                                     std::abs(a->t - b->t) > 1e-5 * (10.0 + a->t)))) {
            if (differing++ < 5)
                MESSAGE("ray " << k << ": " << (a ? int(a->triangle.mesh) : -1) << "/" << (a ? int(a->triangle.triangle) : -1)
                               << " t " << (a ? a->t : 0.0) << " vs " << (b ? int(b->triangle.mesh) : -1) << "/"
                               << (b ? int(b->triangle.triangle) : -1) << " t " << (b ? b->t : 0.0));
            continue;
        }
        if (!a) continue;
        ++hits;
        least += a->triangle.mesh % 2 == 0 ? 1 : 0;  // the outward copy comes first
    }
    MESSAGE(hits << " hits on coincident faces");
    CHECK(hits > 500);
    CHECK(differing == 0);
    CHECK(least == hits);
}
