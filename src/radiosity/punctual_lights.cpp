#include "radiosity/punctual_lights.h"

#include <algorithm>
#include <cmath>

#include "geometry/polygon.h"
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

DVec3 pointAtInfinity(const RayCaster& caster, const DVec3& p_world, const DVec3& direction) {
    // The scene lies within half its diagonal of its centre, so going that far past p's own
    // distance from the centre leaves it; the margin clears the end offset.
    const Aabb bounds = caster.sceneBounds();
    const double from_centre = bounds.empty() ? 0.0 : glm::length(p_world - bounds.center());
    const double reach = from_centre + 0.5 * caster.sceneExtent() + 4.0 * caster.epsilon();
    return p_world + reach * direction;
}

namespace {

// Per-channel strength, negative values clamped to zero (VRML clamps intensity to [0, 1]; we
// allow > 1, since real files use it as a brightness scale).
DVec3 strength(const Light& light) {
    return glm::max(DVec3(light.color) * std::max(double(light.intensity), 0.0), DVec3(0.0));
}

// Direct light from a disc at infinity (Light::angular_diameter > 0): E times the mean over
// points of the disc of the visible cosine, normalised by the mean cosine of a plane facing it,
// so such a plane unshadowed reads E. Eight points on a ring near its rim first (an edge that
// leaves them all on one side hides at most 4 % of the disc); where they disagree (a penumbra),
// 6 x 6 points over the disc.
DVec3 discIrradiance(const DVec3& power, double angular_diameter, const RayCaster* caster, const DVec3& p_world,
                     const DVec3& n_world, const DVec3& towards_light, size_t* rays_cast) {
    DVec3 e1, e2;
    tangentFrame(towards_light, e1, e2);
    const double spread = std::tan(0.5 * std::min(angular_diameter, 0.99 * kPi));
    double sum = 0.0, facing = 0.0;
    int seen = 0, tried = 0;
    auto add = [&](const DVec2& disc) {  // a point of the unit disc
        const DVec3 d = glm::normalize(towards_light + spread * (disc.x * e1 + disc.y * e2));
        facing += glm::dot(d, towards_light);
        const double cosine = glm::dot(n_world, d);
        if (!(cosine > 0.0)) return;
        ++tried;
        double through = 1.0;
        if (caster) {
            if (rays_cast) ++*rays_cast;
            through = caster->transmittance(p_world, pointAtInfinity(*caster, p_world, d));
            if (through == 0.0) return;
        }
        sum += cosine * through, ++seen;
    };
    constexpr int kRing = 8;
    for (int k = 0; k < kRing; ++k) {
        const double phi = (k + 0.5) * 2.0 * kPi / kRing;
        add(0.9 * DVec2(std::cos(phi), std::sin(phi)));
    }
    if (seen != 0 && seen != tried) {
        // Cell centres of a 6 x 6 grid on the square, mapped onto the disc by equal areas.
        constexpr int kGrid = 6;
        sum = facing = 0.0;
        for (int i = 0; i < kGrid; ++i)
            for (int j = 0; j < kGrid; ++j) {
                add(concentricDisc(2.0 * (i + 0.5) / kGrid - 1.0, 2.0 * (j + 0.5) / kGrid - 1.0));
            }
    }
    return facing > 0.0 ? power * (sum / facing) : DVec3(0.0);
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
        if (light.angular_diameter > 0.0f && cos_theta > -std::sin(0.5 * double(light.angular_diameter)))
            return discIrradiance(power, light.angular_diameter, caster, p_world, n_world, towards_light, rays_cast);
        if (!(cos_theta > 0.0)) return DVec3(0.0);
        double through = 1.0;
        if (caster) {
            if (rays_cast) ++*rays_cast;
            through = caster->transmittance(p_world, pointAtInfinity(*caster, p_world, towards_light));
        }
        return power * (cos_theta * through);
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
    double through = 1.0;
    if (caster) {
        if (rays_cast) ++*rays_cast;
        through = caster->transmittance(p_world, DVec3(light.position));
    }
    return power * (through * cos_theta / (distance * distance) * attenuationFactor(light.attenuation, distance) * spot);
}

DVec3 punctualIrradiance(std::span<const Light> lights, const RayCaster* caster, const DVec3& p_world,
                         const DVec3& n_world, size_t* rays_cast, uint32_t receiver_mesh, LightSet set) {
    DVec3 total(0.0);
    for (const Light& light : lights)
        if ((receiver_mesh == kAnyMesh || light.lights(receiver_mesh)) && !(set == LightSet::Baked && light.realtime))
            total += lightIrradiance(light, caster, p_world, n_world, rays_cast);
    return total;
}

}  // namespace radbake
