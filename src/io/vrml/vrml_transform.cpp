#include "io/vrml/vrml_transform.h"

#include <cmath>
#include <utility>

namespace radbake::vrml {

DMat4 rotationMatrix(const DVec3& axis, double angle) {
    const double length = glm::length(axis);
    if (!(length > 0.0) || !std::isfinite(length) || !std::isfinite(angle)) return DMat4(1.0);
    return DMat4(glm::mat3_cast(glm::angleAxis(angle, axis / length)));
}

DMat4 translationMatrix(const Vec3& t) {
    DMat4 m(1.0);
    m[3] = glm::dvec4(DVec3(t), 1.0);
    return m;
}

DMat4 scaleMatrix(const Vec3& s) {
    DMat4 m(1.0);
    m[0][0] = s.x;
    m[1][1] = s.y;
    m[2][2] = s.z;
    return m;
}

Vec3 transformPoint(const DMat4& m, const Vec3& p) {
    const glm::dvec4 r = m * glm::dvec4(DVec3(p), 1.0);
    const double w = (r.w != 0.0 && std::isfinite(r.w)) ? r.w : 1.0;  // affine in practice
    return Vec3(DVec3(r) / w);
}

Vec3 transformDirection(const DMat4& m, const Vec3& d, const Vec3& fallback) {
    const DVec3 r = DMat3(m) * DVec3(d);
    const double length = glm::length(r);
    return length > 0.0 && std::isfinite(length) ? Vec3(r / length) : fallback;
}

Quat rotationOf(const DMat4& m) {
    DMat3 r(m);
    for (int c = 0; c < 3; ++c) {
        const double length = glm::length(r[c]);
        if (!(length > 0.0)) return Quat(1, 0, 0, 0);
        r[c] /= length;
    }
    if (glm::determinant(r) < 0.0) r[2] = -r[2];
    return Quat(glm::quat_cast(r));
}

void transformAppended(Scene& scene, size_t first_mesh, size_t first_light, size_t first_camera,
                       const DMat4& m) {
    const DMat3 linear(m);
    const bool mirrored = glm::determinant(linear) < 0.0;
    const DMat3 normal_matrix = glm::transpose(glm::inverse(linear));
    const double scale = std::cbrt(std::abs(glm::determinant(linear)));
    for (size_t i = first_mesh; i < scene.meshes.size(); ++i) {
        Mesh& mesh = scene.meshes[i];
        for (Vec3& p : mesh.positions) p = transformPoint(m, p);
        for (Vec3& n : mesh.normals) n = transformDirection(DMat4(normal_matrix), n, n);
        if (mirrored)
            for (UVec3& t : mesh.triangles) std::swap(t.y, t.z);
    }
    for (size_t i = first_light; i < scene.lights.size(); ++i) {
        Light& light = scene.lights[i];
        light.position = transformPoint(m, light.position);
        light.direction = transformDirection(m, light.direction, light.direction);
        if (light.type != LightType::Directional) light.radius = float(light.radius * scale);
    }
    const Quat rotation = rotationOf(m);
    for (size_t i = first_camera; i < scene.cameras.size(); ++i) {
        Camera& camera = scene.cameras[i];
        camera.position = transformPoint(m, camera.position);
        camera.orientation = glm::normalize(rotation * camera.orientation);
    }
}

}  // namespace radbake::vrml
