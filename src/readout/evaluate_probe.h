#pragma once
// The exhaustive gather: the light at any point read from every root of a solved hierarchy
// (the read-out's reference), with counters of the work it does for benchmarks
// (tools/bench_probes) and tests that check how much an evaluation casts.
#include <array>
#include <cstddef>
#include <span>

#include "radiosity/solution.h"
#include "readout/readout_options.h"

namespace radbake {

struct ProbeCounters {
    size_t rays = 0;          // visibility segments cast from the probe (punctual lights excluded)
    size_t form_factors = 0;  // point-to-polygon form factors evaluated
    size_t pieces = 0;        // elements and sub-leaf pieces that contributed light
};

// Points read and the work they took.
struct ReadoutWork {
    size_t points = 0;
    ProbeCounters counts;
    // Shards' work adds up: each point's work is its own.
    ReadoutWork& operator+=(const ReadoutWork& o) {
        points += o.points;
        counts.rays += o.counts.rays;
        counts.form_factors += o.counts.form_factors;
        counts.pieces += o.counts.pieces;
        return *this;
    }
    ReadoutWork operator-(const ReadoutWork& o) const {
        ReadoutWork d = *this;
        d.points -= o.points;
        d.counts.rays -= o.counts.rays;
        d.counts.form_factors -= o.counts.form_factors;
        d.counts.pieces -= o.counts.pieces;
        return d;
    }
};

// Irradiance H (W/m^2, DESIGN.md section 2) arriving at `point` on a surface facing `normal`
// (unit), gathered from the solved hierarchy (point-to-polygon form factors, visibility by
// rays) plus the direct light of punctual lights. Per channel. A point on a surface of
// Scene::meshes[receiver_mesh] takes only the punctual lights whose scope holds that mesh
// (Light::lights: a VRML DirectionalLight lights its siblings only); a probe
// (receiver_mesh = 0xffffffff, punctual_lights.h's kAnyMesh) takes them all.
DVec3 probeIrradiance(const Solution& solution, const ReadoutOptions& options, const DVec3& point, const DVec3& normal,
                      uint32_t receiver_mesh = 0xffffffffu);

// The same answer as probeIrradiance, bit for bit; `counters` is incremented.
DVec3 probeIrradianceCounted(const Solution& solution, const ReadoutOptions& options, const DVec3& point,
                             const DVec3& normal, ProbeCounters& counters, uint32_t receiver_mesh = 0xffffffffu);

// The same gather at a point of triangle `triangle` of Scene::meshes[mesh] (a vertex, a texel's
// point), whose punctual lights are read from just inside that triangle (gather.h,
// punctualInside): its value is the limit from inside its face.
DVec3 surfaceIrradiance(const Solution& solution, const ReadoutOptions& options, const DVec3& point, const DVec3& normal,
                        uint32_t mesh, uint32_t triangle, ProbeCounters* counters = nullptr);

// Pieces of probeIrradiance, exposed for tests.

// splitPolygon (radiosity/elements.h) of a quad, to the bit, without heap allocations: pieces
// below a leaf are split by the thousand per probe.
struct QuadChildren {
    std::array<std::array<DVec3, 4>, 4> loops;
    size_t count = 0;  // 2 (a long quad halved) or 4
};
void splitQuad(std::span<const DVec3> loop, QuadChildren& out);

}  // namespace radbake
