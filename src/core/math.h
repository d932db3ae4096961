#pragma once
// The one place that includes GLM. Geometry is stored as float; energy, form factors and
// anything accumulated is computed in double (DVec3).
#include <cmath>

#define GLM_FORCE_XYZW_ONLY
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/norm.hpp>

namespace radbake {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using DVec2 = glm::dvec2;
using DVec3 = glm::dvec3;
using Mat3 = glm::mat3;
using Mat4 = glm::mat4;
using DMat4 = glm::dmat4;
using Quat = glm::quat;
using UVec3 = glm::uvec3;

inline constexpr double kPi = 3.14159265358979323846;

// atan(u) for |u| <= tan(pi / 8): u + u^3 P(u^2), P from tools/gen_atan_coefficients.py.
// T: double, or a GCC vector of doubles (the same operations on every lane).
template <class T>
inline T atanSmall(const T& u) {
    const T z = u * u;
    T p = T{} + 0.022750511120272942;
    p = p * z - 0.044833334623513882;
    p = p * z + 0.057363318138629805;
    p = p * z - 0.066496136378790052;
    p = p * z + 0.076910551529583357;
    p = p * z - 0.090908525568752341;
    p = p * z + 0.11111109636525059;
    p = p * z - 0.14285714266096475;
    p = p * z + 0.19999999999898407;
    p = p * z - 0.33333333333333248;
    return u + u * z * p;
}

// atan2(y, x) for y >= 0 (an angle in [0, pi]: the angle between two vectors, y = |a x b|,
// x = a . b), to within 3e-16 relative of std::atan2 and about three times as fast: the point
// form factor spends most of its time here. Reduced to atan(u), |u| <= tan(pi / 8), by
// atan2(y, x) = pi/2 - atan(x / y) and atan(r) = pi/4 + atan((r - 1) / (r + 1)).
inline double atan2Upper(double y, double x) {
    const double ax = std::abs(x);
    const bool steep = y > ax;  // the angle from the x axis is above pi/4
    const double a = steep ? ax : y, b = steep ? y : ax;  // a <= b
    if (!(b > 0.0)) return x < 0.0 ? kPi : 0.0;  // both zero: std::atan2's answer
    constexpr double kTanPi8 = 0.41421356237309504880;
    const bool reduce = a > kTanPi8 * b;
    const double u = reduce ? (a - b) / (a + b) : a / b;
    double angle = atanSmall(u);  // atan(a / b) in [0, pi/4]
    if (reduce) angle += 0.25 * kPi;
    if (steep) angle = 0.5 * kPi - angle;
    return x < 0.0 ? kPi - angle : angle;
}

// Folds v into the running hash h (a signature of what a cached value was computed from).
inline uint64_t mixHash(uint64_t h, uint64_t v) {
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 31;
    return h * 0xbf58476d1ce4e5b9ull;
}

// Shirley and Chiu's concentric map: the point (a, b) of the square [-1, 1]^2 onto the unit disc,
// preserving areas up to the constant pi / 4 and keeping neighbours near.
inline DVec2 concentricDisc(double a, double b) {
    if (a == 0.0 && b == 0.0) return DVec2(0.0);
    if (std::abs(a) > std::abs(b)) {
        const double phi = 0.25 * kPi * (b / a);
        return a * DVec2(std::cos(phi), std::sin(phi));
    }
    const double phi = 0.5 * kPi - 0.25 * kPi * (a / b);
    return b * DVec2(std::cos(phi), std::sin(phi));
}

inline bool isFinite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace radbake
