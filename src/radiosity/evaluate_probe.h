#pragma once
// probeIrradiance (radiosity/solution.h) with counters of the work it does, for benchmarks
// (tools/bench_probes) and tests that check how much an evaluation casts.
#include <array>
#include <cstddef>
#include <span>

#include "radiosity/solution.h"

namespace radbake {

struct ProbeCounters {
    size_t rays = 0;          // visibility segments cast from the probe (punctual lights excluded)
    size_t form_factors = 0;  // point-to-polygon form factors evaluated
    size_t pieces = 0;        // elements and sub-leaf pieces that contributed light
};

// The same answer as probeIrradiance, bit for bit; `counters` is incremented.
DVec3 probeIrradianceCounted(const Solution& solution, const DVec3& point, const DVec3& normal,
                             ProbeCounters& counters, uint32_t receiver_mesh = 0xffffffffu);

// Pieces of probeIrradiance, exposed for tests.

// splitPolygon (radiosity/elements.h) of a quad, to the bit, without heap allocations: pieces
// below a leaf are split by the thousand per probe.
struct QuadChildren {
    std::array<std::array<DVec3, 4>, 4> loops;
    size_t count = 0;  // 2 (a long quad halved) or 4
};
void splitQuad(std::span<const DVec3> loop, QuadChildren& out);

// pointPolygonFormFactor (radiosity/form_factor.h), to the bit, with a fast path for a quad
// wholly above the point's horizon (no clipping).
double piecePointFormFactor(const DVec3& point, const DVec3& normal, std::span<const DVec3> source,
                            const DVec3& source_normal);

}  // namespace radbake
