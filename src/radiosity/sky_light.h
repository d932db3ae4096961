#pragma once
// Direct light from the sky (Scene::sky, scene/daylight.h) at a point, with visibility by rays:
// an adaptive quadrature over the hemisphere, deterministic (no random numbers), so the same
// point reads the same light on any thread. The solve reads it at every element corner
// (Solution::vertex_sky; elements split where their corners differ, as for punctual lights) and
// adds rho times the corners' mean to the element's radiosity, so it bounces; vertices and texels
// take it from their leaf's corners (skyInElement), probes and the exhaustive gather at the point.
//
// The hemisphere about the normal is mapped onto the unit square by equal-area maps (the square
// onto the disc, the normal at its centre; the disc onto the hemisphere), so d omega is 2 pi du dv
// and the samples are as dense at the horizon as at the normal. The frame turns the up axis to the
// square's v axis, so a vertical surface's horizon lies on a cell edge (v = 1/2) for an even grid.
// A cell is read at its four quarter centres (the midpoint rule on L V cos theta); where they, or
// the samples across its edges, disagree on whether the sky is seen (a window's outline, a roof's
// edge, the horizon), it is split into its quarters, down to `depth` levels. A feature smaller than
// the top samples' spacing (a small window seen from afar) can fall between them: `grid` sets that
// spacing.
#include <cstddef>

#include "core/math.h"
#include "radiosity/solver_options.h"
#include "scene/scene.h"

namespace radbake {

class RayCaster;
struct Solution;

// Sky irradiance H (W/m^2 per channel) at p_world on the side n_world (unit) faces. `caster`
// may be null (no shadows). rays_cast, when given, is incremented by the rays cast.
DVec3 skyIrradiance(const Sky& sky, const RayCaster* caster, const DVec3& p_world, const DVec3& n_world,
                    const SkyQuadrature& quadrature, size_t* rays_cast = nullptr);

// The sky at point p (on the plane of) element `element`, from the sky at its corners
// (Solution::vertex_sky): bilinear over a quad, else linear over the fan of triangles from its
// first corner.
DVec3 skyInElement(const Solution& solution, uint32_t element, const DVec3& p);

}  // namespace radbake
