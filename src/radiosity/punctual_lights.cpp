#include "radiosity/punctual_lights.h"

#include <algorithm>
#include <cmath>

#include "visibility/ray_caster.h"

namespace radbake {

double spotFactor(double angle, double beam_width, double cut_off_angle) {
    if (!(angle < cut_off_angle)) return 0.0;
    if (angle <= beam_width || beam_width >= cut_off_angle) return 1.0;
    return (angle - cut_off_angle) / (beam_width - cut_off_angle);
}

double attenuationFactor(const Vec3& attenuation, double distance) {
    const double denominator = double(attenuation.x) + double(attenuation.y) * distance +
                               double(attenuation.z) * distance * distance;
    return 1.0 / std::max(denominator, 1.0);  // max(.., 1) also catches NaN/negative sums
}

namespace {

// Per-channel strength, negative values clamped to zero (VRML clamps intensity to [0, 1]; we
// allow > 1, since real files use it as a brightness scale).
DVec3 strength(const Light& light) {
    return glm::max(DVec3(light.color) * std::max(double(light.intensity), 0.0), DVec3(0.0));
}

// A point far enough from p_world against the light's direction to be outside every
// triangle: the scene lies within half its diagonal of its centre, so going that far past
// p's own distance from the centre leaves it; the margin clears the end offset.
DVec3 pointTowardsDirectionalLight(const RayCaster& caster, const DVec3& p_world, const DVec3& towards_light) {
    const Aabb bounds = caster.sceneBounds();
    const double from_centre = bounds.empty() ? 0.0 : glm::length(p_world - bounds.center());
    const double reach = from_centre + 0.5 * caster.sceneExtent() + 4.0 * caster.epsilon();
    return p_world + reach * towards_light;
}

}  // namespace

DVec3 lightIrradiance(const Light& light, const RayCaster* caster, const DVec3& p_world, const DVec3& n_world,
                      size_t* rays_cast) {
    if (!light.on) return DVec3(0.0);
    const DVec3 power = strength(light);
    if (power == DVec3(0.0)) return DVec3(0.0);

    if (light.type == LightType::Directional) {
        const DVec3 direction(light.direction);
        const double length = glm::length(direction);
        if (!(length > 0.0)) return DVec3(0.0);
        const DVec3 towards_light = -direction / length;
        const double cos_theta = glm::dot(n_world, towards_light);
        if (!(cos_theta > 0.0)) return DVec3(0.0);
        if (caster) {
            if (rays_cast) ++*rays_cast;
            if (caster->segmentBlocked(p_world, pointTowardsDirectionalLight(*caster, p_world, towards_light)))
                return DVec3(0.0);
        }
        return power * cos_theta;
    }

    const DVec3 to_light = DVec3(light.position) - p_world;
    const double distance = glm::length(to_light);
    if (!(distance > 0.0) || distance > double(light.radius)) return DVec3(0.0);
    const DVec3 towards_light = to_light / distance;
    const double cos_theta = glm::dot(n_world, towards_light);
    if (!(cos_theta > 0.0)) return DVec3(0.0);

    double spot = 1.0;
    if (light.type == LightType::Spot) {
        const DVec3 axis(light.direction);
        const double axis_length = glm::length(axis);
        if (!(axis_length > 0.0)) return DVec3(0.0);
        const double cos_angle = std::clamp(glm::dot(-towards_light, axis / axis_length), -1.0, 1.0);
        spot = spotFactor(std::acos(cos_angle), light.beam_width, light.cut_off_angle);
        if (spot == 0.0) return DVec3(0.0);
    }
    if (caster) {
        if (rays_cast) ++*rays_cast;
        if (caster->segmentBlocked(p_world, DVec3(light.position))) return DVec3(0.0);
    }
    return power * (cos_theta / (distance * distance) * attenuationFactor(light.attenuation, distance) * spot);
}

DVec3 punctualIrradiance(std::span<const Light> lights, const RayCaster* caster, const DVec3& p_world,
                         const DVec3& n_world, size_t* rays_cast, uint32_t receiver_mesh) {
    DVec3 total(0.0);
    for (const Light& light : lights)
        if (receiver_mesh == kAnyMesh || light.lights(receiver_mesh))
            total += lightIrradiance(light, caster, p_world, n_world, rays_cast);
    return total;
}

}  // namespace radbake
