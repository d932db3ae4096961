// Form factors against closed forms (unit squares, Howell's catalogue values).
#include <doctest/doctest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "radiosity/elements.h"
#include "radiosity/form_factor.h"

using namespace radbake;

namespace {

struct Poly {
    std::vector<DVec3> loop;
    Element element;
    PolygonView view() const {
        return {loop, element.normal, element.centroid, element.radius};
    }
};

Poly makePoly(std::vector<DVec3> loop) {
    Poly p{std::move(loop), {}};
    setElementGeometry(p.element, p.loop);
    return p;
}

// Closed forms (Howell, C-11 and C-14) for unit squares.
constexpr double kParallelUnit = 0.199824895698387383;
constexpr double kPerpendicularUnit = 0.200043776075403154;

}  // namespace

TEST_CASE("point-to-polygon form factor: centre below a square (closed form)") {
    // Square of half-side a at height h, centred above the point: each edge, at distance
    // s = sqrt(a^2 + h^2), subtends 2 atan(a / s) in a plane tilted by a / s, so
    // F = 4 / (2 pi) * 2 atan(a / s) * a / s.
    const double a = 0.5, h = 1.0;
    const Poly source = makePoly({{-a, -a, h}, {-a, a, h}, {a, a, h}, {a, -a, h}});  // faces down
    CHECK(source.element.normal.z == doctest::Approx(-1.0));
    const double s = std::sqrt(a * a + h * h);
    const double expected = 4.0 / kPi * (a / s) * std::atan(a / s);  // 0.23945...
    const double f = pointPolygonFormFactor({0, 0, 0}, {0, 0, 1}, source.loop, source.element.normal);
    CHECK(f == doctest::Approx(expected).epsilon(1e-12).scale(0.0));
    // Behind the source or facing away: nothing.
    CHECK(pointPolygonFormFactor({0, 0, 2}, {0, 0, -1}, source.loop, source.element.normal) == 0.0);
    CHECK(pointPolygonFormFactor({0, 0, 0}, {0, 0, -1}, source.loop, source.element.normal) == 0.0);
}

TEST_CASE("point-to-polygon form factor: a polygon straddling the tangent plane is clipped") {
    // A vertical unit square standing on the receiver's plane from x = 0 to 1, facing -y,
    // extended below the plane to z = -1: only the part above the plane counts.
    const Poly tall = makePoly({{0, 1, -1}, {1, 1, -1}, {1, 1, 1}, {0, 1, 1}});
    const Poly upper = makePoly({{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}});
    REQUIRE(tall.element.normal.y == doctest::Approx(-1.0));
    const DVec3 p(0.3, 0.2, 0.0), n(0, 0, 1);
    const double f_tall = pointPolygonFormFactor(p, n, tall.loop, tall.element.normal);
    const double f_upper = pointPolygonFormFactor(p, n, upper.loop, upper.element.normal);
    CHECK(f_upper > 0.05);
    CHECK(f_tall == doctest::Approx(f_upper).epsilon(1e-12).scale(0.0));
}

TEST_CASE("polygon form factor: parallel opposed unit squares at distance 1") {
    const Poly bottom = makePoly({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
    const Poly top = makePoly({{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}});
    const FormFactorEstimate f = polygonFormFactor(bottom.view(), top.view(), QuadratureOptions{});
    CHECK(f.form_factor == doctest::Approx(kParallelUnit).epsilon(1e-5).scale(0.0));
    CHECK(f.f_min < f.form_factor);
    CHECK(f.f_max > f.form_factor);
    // Reciprocity (equal areas): the other way round gives the same.
    const FormFactorEstimate g = polygonFormFactor(top.view(), bottom.view(), QuadratureOptions{});
    CHECK(g.form_factor == doctest::Approx(kParallelUnit).epsilon(1e-5).scale(0.0));
}

TEST_CASE("polygon form factor: perpendicular unit squares sharing an edge") {
    const Poly floor = makePoly({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
    const Poly wall = makePoly({{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}});  // x = 0, faces +x
    REQUIRE(wall.element.normal.x == doctest::Approx(1.0));
    const FormFactorEstimate f = polygonFormFactor(floor.view(), wall.view(), QuadratureOptions{});
    MESSAGE("perpendicular F = " << f.form_factor << " samples " << f.samples);
    CHECK(f.form_factor == doctest::Approx(kPerpendicularUnit).epsilon(2e-4).scale(0.0));
    QuadratureOptions fine;
    fine.max_depth = 9;
    const FormFactorEstimate g = polygonFormFactor(floor.view(), wall.view(), fine);
    MESSAGE("perpendicular F (depth 9) = " << g.form_factor << " samples " << g.samples);
    CHECK(g.form_factor == doctest::Approx(kPerpendicularUnit).epsilon(2e-5).scale(0.0));
}

TEST_CASE("polygon form factor: touching pairs are exact at the presets' quadrature (graded across the edge)") {
    // A closed room at rho = 0.999 amplifies a relative error e of its touching links into
    // ~1000 e of its light: the medium preset's quadrature (order 3, near 0.5, depth 2) must
    // give perpendicular unit squares to 1e-5 (isotropic splitting gave 2e-5 only at depth 9).
    QuadratureOptions medium;
    medium.order = 3;
    medium.near_ratio = 0.5;
    medium.max_depth = 2;
    const Poly floor = makePoly({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
    const Poly wall = makePoly({{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}});
    const FormFactorEstimate f = polygonFormFactor(floor.view(), wall.view(), medium);
    MESSAGE("perpendicular F (medium): relative error " << (f.form_factor / kPerpendicularUnit - 1.0) << ", samples " << f.samples);
    CHECK(f.form_factor == doctest::Approx(kPerpendicularUnit).epsilon(1e-5).scale(0.0));
    // The same pair scaled by 1e-3 and 1e3: the grading is relative.
    for (const double scale : {1e-3, 1e3}) {
        std::vector<DVec3> a = floor.loop, b = wall.loop;
        for (DVec3& p : a) p *= scale;
        for (DVec3& p : b) p *= scale;
        const Poly fa = makePoly(a), wb = makePoly(b);
        CHECK(polygonFormFactor(fa.view(), wb.view(), medium).form_factor ==
              doctest::Approx(kPerpendicularUnit).epsilon(1e-5).scale(0.0));
    }
}

TEST_CASE("batched point form factors are the scalar ones to the bit") {
    // Random points and normals around random convex polygons (triangles to hexagons): in front,
    // behind, with the horizon cutting the source, and on its vertices (edges of zero length).
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto randomUnit = [&] {
        DVec3 v;
        do v = DVec3(unit(rng), unit(rng), unit(rng));
        while (glm::length(v) < 0.1 || glm::length(v) > 1.0);
        return glm::normalize(v);
    };
    size_t clipped = 0, behind = 0, whole = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const size_t n = 3 + trial % 4;
        std::vector<DVec3> loop;
        const DVec3 centre(unit(rng), unit(rng), unit(rng));
        const double scale = std::pow(10.0, 3.0 * unit(rng));
        for (size_t i = 0; i < n; ++i) {
            const double angle = 2.0 * kPi * (static_cast<double>(i) + 0.3 * unit(rng)) / static_cast<double>(n);
            loop.push_back(scale * (centre + DVec3(std::cos(angle), std::sin(angle), 0.0)));
        }
        const Poly source = makePoly(loop);
        std::vector<DVec3> points;
        for (int k = 0; k < 1 + trial % 11; ++k) {
            DVec3 p = scale * (centre + 2.0 * DVec3(unit(rng), unit(rng), unit(rng)));
            if (k == 3) p = loop[0];
            points.push_back(p);
        }
        const DVec3 normal = trial % 3 == 0 ? -source.element.normal : randomUnit();
        std::vector<double> batched(points.size(), -1.0);
        pointPolygonFormFactors(points, normal, loop, source.element.normal, batched.data());
        for (size_t k = 0; k < points.size(); ++k) {
            const double scalar = pointPolygonFormFactor(points[k], normal, loop, source.element.normal);
            CHECK(std::bit_cast<uint64_t>(batched[k]) == std::bit_cast<uint64_t>(scalar));
            std::array<DVec3, kMaxClip> out;
            if (!(glm::dot(source.element.normal, points[k] - loop[0]) > 0.0)) ++behind;
            else if (clipAboveHorizon(points[k], normal, loop, out.data()) == n) ++whole;
            else ++clipped;
        }
    }
    // Every path was taken often.
    CHECK(whole > 1000);
    CHECK(clipped > 1000);
    CHECK(behind > 1000);
}

TEST_CASE("point form factors to several sources are the scalar ones to the bit") {
    // Runs of random convex polygons (mixed vertex counts, so pairs and singles both occur) seen
    // from random points: in front, behind and across the horizon.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    size_t compared = 0, positive = 0;
    for (int trial = 0; trial < 500; ++trial) {
        std::vector<Poly> polys;
        for (int k = 0; k < 1 + trial % 9; ++k) {
            const size_t n = (trial + k) % 5 == 0 ? 3 : 4;
            const DVec3 centre(3.0 * unit(rng), 3.0 * unit(rng), 2.0 + unit(rng));
            std::vector<DVec3> loop;
            for (size_t i = 0; i < n; ++i) {
                const double angle = -2.0 * kPi * (static_cast<double>(i) + 0.3 * unit(rng)) / static_cast<double>(n);
                loop.push_back(centre + 0.5 * DVec3(std::cos(angle), std::sin(angle), 0.0));
            }
            polys.push_back(makePoly(loop));
        }
        const DVec3 point(unit(rng), unit(rng), trial % 4 == 0 ? 2.5 : 0.5 * unit(rng));
        const DVec3 normal = glm::normalize(DVec3(0.5 * unit(rng), 0.5 * unit(rng), 1.0));
        std::vector<PolygonView> views;
        for (const Poly& p : polys) views.push_back(p.view());
        std::vector<double> batched(views.size(), -1.0);
        pointPolygonFormFactorsTo(point, normal, views, batched.data());
        for (size_t k = 0; k < views.size(); ++k) {
            const double scalar = pointPolygonFormFactor(point, normal, views[k].vertices, views[k].normal);
            CHECK(std::bit_cast<uint64_t>(batched[k]) == std::bit_cast<uint64_t>(scalar));
            ++compared;
            positive += scalar > 0.0;
        }
    }
    CHECK(compared > 2000);
    CHECK(positive > 500);
}
