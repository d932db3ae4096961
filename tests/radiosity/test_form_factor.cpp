// Form factors against closed forms (unit squares, Howell's catalogue values).
#include <doctest/doctest.h>

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
