#pragma once
// Transform helpers shared by the VRML97 and VRML 1.0 readers.
#include <cstddef>

#include "core/math.h"
#include "scene/scene.h"

namespace radbake::vrml {

using DMat3 = glm::dmat3;

DMat4 rotationMatrix(const DVec3& axis, double angle);  // a zero or non-finite axis: identity
inline DMat4 rotationMatrix(const Vec4& axis_angle) {
    return rotationMatrix(DVec3(axis_angle.x, axis_angle.y, axis_angle.z), axis_angle.w);
}
DMat4 translationMatrix(const Vec3& t);
DMat4 scaleMatrix(const Vec3& s);

Vec3 transformPoint(const DMat4& m, const Vec3& p);
// The direction transformed and normalised; `fallback` when it degenerates.
Vec3 transformDirection(const DMat4& m, const Vec3& d, const Vec3& fallback);
// The rotation part of a matrix that may also scale or mirror (no shear expected).
Quat rotationOf(const DMat4& m);

// Places what was appended to `scene` after the given sizes (an Inline's content, a light, a
// camera) by `world_from_object`: points, normals (inverse transpose), light positions,
// directions and radii, camera poses; flips triangle winding when the matrix mirrors.
void transformAppended(Scene& scene, size_t first_mesh, size_t first_light, size_t first_camera,
                       const DMat4& world_from_object);

}  // namespace radbake::vrml
