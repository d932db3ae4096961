#pragma once
// The one place that includes GLM. Geometry is stored as float; energy, form factors and
// anything accumulated is computed in double (DVec3).
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

inline bool isFinite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace radbake
