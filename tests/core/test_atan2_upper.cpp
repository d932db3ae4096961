// atan2Upper (core/math.h) against std::atan2: the point form factor's angle.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "core/math.h"

using namespace radbake;

namespace {

// Error against std::atan2, relative to the angle (absolute near 0 would hide a wrong
// leading term for a distant polygon's tiny angles), with a floor of one ulp of pi.
double error(double y, double x) {
    const double exact = std::atan2(y, x);
    return std::abs(atan2Upper(y, x) - exact) / std::max(exact, 4e-16);
}

}  // namespace

TEST_CASE("atan2Upper agrees with std::atan2 over the upper half plane") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> angle(0.0, kPi), scale(-30.0, 30.0);
    double worst = 0.0;
    for (int i = 0; i < 1000000; ++i) {
        const double a = angle(rng), r = std::pow(10.0, scale(rng));
        worst = std::max(worst, error(r * std::sin(a), r * std::cos(a)));
    }
    CHECK(worst < 1e-15);
}

TEST_CASE("atan2Upper at the ends and the reduction boundaries") {
    CHECK(atan2Upper(0.0, 1.0) == 0.0);
    CHECK(atan2Upper(0.0, -1.0) == kPi);
    CHECK(atan2Upper(0.0, 0.0) == std::atan2(0.0, 0.0));
    CHECK(atan2Upper(1.0, 0.0) == doctest::Approx(0.5 * kPi).epsilon(1e-16));
    // Tiny angles keep their relative accuracy (a far polygon seen from a point).
    for (const double y : {1e-300, 1e-200, 1e-20, 1e-9, 1e-3}) {
        CHECK(error(y, 1.0) < 1e-15);
        CHECK(error(y, -1.0) < 1e-15);  // nearly opposite vectors: pi - tiny
        CHECK(error(1.0, y) < 1e-15);
    }
    // Either side of each switch: y = x (pi/4), y = tan(pi/8) x, and the mirror images.
    for (const double t : {0.41421356237309504880, 1.0, 2.41421356237309504880})
        for (const double d : {-1e-12, 0.0, 1e-12}) {
            CHECK(error(t * (1.0 + d), 1.0) < 1e-15);
            CHECK(error(t * (1.0 + d), -1.0) < 1e-15);
        }
}
