// The sky's read-out inside an element (radiosity/sky_light.h): the corners' values interpolated
// bilinearly over a quad, against the forward bilinear map, and linearly over a triangle.
#include <doctest/doctest.h>

#include <cmath>

#include "radiosity/sky_light.h"
#include "radiosity/solution.h"

using namespace radbake;

namespace {

Solution withElement(const std::vector<DVec3>& corners, const std::vector<DVec3>& values) {
    Solution s;
    s.vertices = corners;
    s.vertex_sky = values;
    Element e;
    e.first_vertex = 0;
    e.vertex_count = static_cast<uint32_t>(corners.size());
    e.normal = glm::normalize(glm::cross(corners[1] - corners[0], corners[2] - corners[0]));
    s.elements.push_back(e);
    return s;
}

template <class T>
T bilinear(const T* q, double u, double v) {
    return q[0] * ((1 - u) * (1 - v)) + q[1] * (u * (1 - v)) + q[2] * (u * v) + q[3] * ((1 - u) * v);
}

}  // namespace

TEST_CASE("sky in an element: bilinear over a skewed quad, exact at every point the forward map gives") {
    // A convex quad, no two sides parallel, tilted out of every axis plane.
    const DVec3 x = glm::normalize(DVec3(1, 0.2, -0.3)), z = glm::normalize(glm::cross(x, DVec3(0.1, 1, 0.2)));
    const DVec3 y = glm::cross(z, x), o(3, -2, 5);
    const std::vector<DVec3> corners = {o, o + 2.0 * x, o + 2.4 * x + 1.5 * y, o - 0.3 * x + 1.0 * y};
    const std::vector<DVec3> values = {DVec3(1, 2, 3), DVec3(4, 0, 1), DVec3(0.5, 7, 2), DVec3(3, 3, 0)};
    const Solution s = withElement(corners, values);
    for (double u : {0.0, 0.13, 0.5, 0.77, 1.0})
        for (double v : {0.0, 0.31, 0.5, 0.9, 1.0}) {
            const DVec3 p = bilinear(corners.data(), u, v) + 1e-3 * z;  // a little off the plane
            const DVec3 got = skyInElement(s, 0, p), want = bilinear(values.data(), u, v);
            CAPTURE(u);
            CAPTURE(v);
            CHECK(glm::length(got - want) < 1e-9 * glm::length(want));
        }
    // Outside the quad: the nearest edge's value (clamped), never an extrapolation.
    const DVec3 beyond = skyInElement(s, 0, bilinear(corners.data(), 1.4, 0.5));
    CHECK(glm::length(beyond - bilinear(values.data(), 1.0, 0.5)) < 1e-6);
}

TEST_CASE("sky in an element: linear over a triangle") {
    const std::vector<DVec3> corners = {DVec3(0, 0, 0), DVec3(2, 0, 0), DVec3(0, 3, 0)};
    const std::vector<DVec3> values = {DVec3(1), DVec3(3), DVec3(7)};
    const Solution s = withElement(corners, values);
    const DVec3 got = skyInElement(s, 0, DVec3(0.5, 0.75, 0));  // weights 0.5, 0.25, 0.25
    CHECK(got.x == doctest::Approx(0.5 * 1 + 0.25 * 3 + 0.25 * 7));
}
