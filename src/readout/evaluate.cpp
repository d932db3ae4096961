// Evaluation of the solved hierarchy at arbitrary points: probes and baked vertices.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "geometry/polygon.h"
#include "radiosity/elements.h"
#include "readout/evaluate_probe.h"
#include "radiosity/form_factor.h"
#include "readout/gather.h"
#include "radiosity/punctual_lights.h"
#include "radiosity/refine.h"
#include "radiosity/solution.h"
#include "visibility/ray_caster.h"

namespace radbake {

// The same arithmetic as splitPolygon's quad branch (elements.cpp), in the same order, so the
// same children to the bit: keep them in step; test_probe_split.cpp compares them.
void splitQuad(std::span<const DVec3> loop, QuadChildren& out) {
    const double len02 = glm::length(loop[1] - loop[0]) + glm::length(loop[3] - loop[2]);
    const double len13 = glm::length(loop[2] - loop[1]) + glm::length(loop[0] - loop[3]);
    if (len02 > 2.0 * len13 || len13 > 2.0 * len02) {
        const int a = len02 > len13 ? 0 : 1;
        const DVec3& p0 = loop[a];
        const DVec3& p1 = loop[(a + 1) % 4];
        const DVec3& p2 = loop[(a + 2) % 4];
        const DVec3& p3 = loop[(a + 3) % 4];
        const DVec3 m01 = 0.5 * (p0 + p1), m23 = 0.5 * (p2 + p3);
        out.loops[0] = {p0, m01, m23, p3};
        out.loops[1] = {m01, p1, p2, m23};
        out.count = 2;
        return;
    }
    const DVec3 centre = 0.25 * (loop[0] + loop[1] + loop[2] + loop[3]);
    for (size_t i = 0; i < 4; ++i) {
        const DVec3& v = loop[i];
        const DVec3 next_mid = 0.5 * (v + loop[(i + 1) % 4]);
        const DVec3 prev_mid = 0.5 * (v + loop[(i + 3) % 4]);
        out.loops[i] = {v, next_mid, centre, prev_mid};
    }
    out.count = 4;
}

namespace {

DVec3 evaluate(const Solution& solution, const ReadoutOptions& options, const DVec3& point_on_surface,
               const DVec3& normal, ProbeCounters* counters, uint32_t receiver_mesh,
               uint32_t receiver_triangle = kNoElement) {
    if (solution.elements.empty()) return DVec3(0.0);
    const double lift = gather::kLift * solution.scene_extent;
    const Scene* scene = solution.scene;
    const bool on_face = scene && receiver_mesh < scene->meshes.size() &&
                         receiver_triangle < scene->meshes[receiver_mesh].triangles.size();
    DVec3 point;
    if (on_face) {
        const Mesh& m = scene->meshes[receiver_mesh];
        const UVec3& t = m.triangles[receiver_triangle];
        point = gather::liftOffFacingSurfaces(solution, point_on_surface, normal, lift,
                                              {DVec3(m.positions[t.x]), DVec3(m.positions[t.y]), DVec3(m.positions[t.z])});
    } else {
        point = gather::liftOffSurfaces(solution, point_on_surface, normal, lift);
    }
    gather::Gatherer g{.s = solution,
               .o = options,
               .point = point,
               .normal = normal,
               .origin = point + lift * normal,
               .lift = lift,
               .counters = counters,
               .use_rays = solution.rays != nullptr};
    g.visitRoots(options.probe_faint_share);
    return g.sum +
           gather::punctualInside(solution, receiver_mesh, receiver_triangle, point_on_surface, normal,
                                  options.sky.grid > 0 ? &options.sky : nullptr);
}

}  // namespace

DVec3 probeIrradiance(const Solution& solution, const ReadoutOptions& options, const DVec3& point, const DVec3& normal,
                      uint32_t receiver_mesh) {
    return evaluate(solution, options, point, normal, nullptr, receiver_mesh);
}

DVec3 probeIrradianceCounted(const Solution& solution, const ReadoutOptions& options, const DVec3& point,
                             const DVec3& normal, ProbeCounters& counters, uint32_t receiver_mesh) {
    return evaluate(solution, options, point, normal, &counters, receiver_mesh);
}

DVec3 surfaceIrradiance(const Solution& solution, const ReadoutOptions& options, const DVec3& point, const DVec3& normal,
                        uint32_t mesh, uint32_t triangle, ProbeCounters* counters) {
    return evaluate(solution, options, point, normal, counters, mesh, triangle);
}

}  // namespace radbake
