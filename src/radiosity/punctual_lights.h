#pragma once
// Direct light from the scene's punctual lights (VRML97 PointLight, SpotLight,
// DirectionalLight), with visibility by rays. What they light then bounces through the
// radiosity solution: the solver adds rho * H_direct to each element's radiosity.
//
// Units. VRML's `intensity` is dimensionless (a [0, 1] scale of a light's colour in VRML's
// local lighting equation); radbake gives it radiometric meaning:
//   - PointLight / SpotLight: radiant intensity I = intensity * color, in W/sr per channel.
//     At distance d and incidence angle theta the irradiance is
//       H = I cos(theta) / d^2 * attenuation * spot,
//     with VRML's attenuation factor 1 / max(a0 + a1 d + a2 d^2, 1) (1 for the default
//     attenuation 1 0 0: the inverse-square law is always applied), zero beyond `radius`.
//   - DirectionalLight: E = intensity * color is the irradiance, in W/m^2, on a surface facing
//     the light; H = E cos(theta). One with an angular diameter (the sun, scene/daylight.h) is a
//     disc: H is E times the visible share of its cosine-weighted disc, with penumbrae.
// `ambientIntensity` is ignored: the radiosity solution supplies the indirect light that
// VRML's ambient term imitates. A scoped light (Light::scope: a VRML97 DirectionalLight lights
// only its siblings) lights only the meshes of its scope directly; what they reflect reaches
// the rest through the solution.
#include <cstddef>
#include <span>

#include "core/math.h"
#include "scene/scene.h"

namespace radbake {

class RayCaster;

// VRML97 SpotLight factor for a direction at `angle` (radians) from the spot axis: 1 inside
// beam_width, 0 at or beyond cut_off_angle, linear in the angle between. A beam_width larger
// than the cut-off counts as equal to it (VRML97 6.45).
double spotFactor(double angle, double beam_width, double cut_off_angle);

// A point along unit `direction` from p_world beyond every triangle of the caster's scene: the
// far end of a shadow segment towards a light at infinity.
DVec3 pointAtInfinity(const RayCaster& caster, const DVec3& p_world, const DVec3& direction);

// VRML97 attenuation factor 1 / max(a0 + a1 d + a2 d^2, 1).
double attenuationFactor(const Vec3& attenuation, double distance);

// Direct irradiance H (W/m^2 per RGB channel) at p_world on the side of a surface that
// n_world (unit) faces, from one light: zero when the light is off, behind the surface, out
// of range or shadowed. `caster` may be null (no shadows). rays_cast, when given, is
// incremented by the number of shadow segments cast (0 or 1).
DVec3 lightIrradiance(const Light& light, const RayCaster* caster, const DVec3& p_world, const DVec3& n_world,
                      size_t* rays_cast = nullptr);

// A receiver on no mesh in particular (a probe: it has no place in the scene graph), lit by
// every light, scoped or not.
inline constexpr uint32_t kAnyMesh = UINT32_MAX;

// Which lights a sum takes: all of them (the solve: every light's direct light bounces), or
// only those whose direct light is baked (the read-out: not Light::realtime ones).
enum class LightSet { All, Baked };

// Sum of lightIrradiance over the lights that light `receiver_mesh` (Light::lights): a point
// on a surface passes its mesh, so that a scoped light skips the meshes outside its scope.
DVec3 punctualIrradiance(std::span<const Light> lights, const RayCaster* caster, const DVec3& p_world,
                         const DVec3& n_world, size_t* rays_cast = nullptr, uint32_t receiver_mesh = kAnyMesh,
                         LightSet set = LightSet::All);

}  // namespace radbake
