#pragma once
// Direct light from the sky (Scene::sky, scene/daylight.h) at a point, with visibility by rays:
// an adaptive quadrature over the hemisphere, deterministic (no random numbers), so the same
// point reads the same light on any thread. What the sky lights then bounces through the
// radiosity solution as the punctual lights' light does (the solver adds rho * H_direct to each
// element's radiosity).
//
// The hemisphere about the normal is mapped onto the unit square by u = 1 - cos theta,
// v = phi / 2 pi, on which cos theta d omega is 2 pi (1 - u) du dv: linear in u, so the midpoint
// rule integrates an open uniform sky exactly on any partition, and a smooth sky (overcast) to
// O(h^2). The frame turns the up axis to phi = 90 degrees, so a vertical surface's horizon lies on
// cell edges (v = 0, 1/2) for an even grid. A cell is read at its four quarter centres; where they,
// or the samples across its edges, disagree on whether the sky is seen (a window's outline, a
// roof's edge, the horizon), it is split into its quarters, down to `depth` levels. A feature
// smaller than the top samples' spacing (a small window seen from afar) can fall between them:
// `grid` sets that spacing.
#include <cstddef>

#include "core/math.h"
#include "scene/scene.h"

namespace radbake {

class RayCaster;

struct SkyQuadrature {
    int grid = 6;   // grid x grid cells of 4 samples each at the top level (even)
    int depth = 3;  // levels a cell may be split into quarters
};

// The solve's quadrature (per element it is averaged over 3 x 3 points); the read-out's is
// ReadoutOptions::sky.
inline constexpr SkyQuadrature kSolveSkyQuadrature{4, 2};

// Sky irradiance H (W/m^2 per channel) at p_world on the side n_world (unit) faces. `caster`
// may be null (no shadows). rays_cast, when given, is incremented by the rays cast.
DVec3 skyIrradiance(const Sky& sky, const RayCaster* caster, const DVec3& p_world, const DVec3& n_world,
                    const SkyQuadrature& quadrature, size_t* rays_cast = nullptr);

// Whether the scene holds light that is not on a surface: punctual lights or a sky.
inline bool hasDirectLight(const Scene& scene) { return !scene.lights.empty() || scene.sky.shines(); }

// The punctual lights that light `receiver_mesh` (punctual_lights.h) and the sky.
DVec3 directIrradiance(const Scene& scene, const RayCaster* caster, const DVec3& p_world, const DVec3& n_world,
                       const SkyQuadrature& quadrature, size_t* rays_cast, uint32_t receiver_mesh);

}  // namespace radbake
