#pragma once
// Ray-cast visibility over every triangle of a Scene. The implementation (ray_caster.cpp) is
// the only file in the project that includes Embree; this header does not.
//
// Thread safety: build() is single-threaded; after it returns, every const query may be
// called from any number of threads at once. Queries are deterministic: the same inputs give
// the same answer on any thread and any thread count (fixed sample points, no RNG state).
//
// Tolerance: every segment is shortened by epsilon() at BOTH ends, so a segment that starts or
// ends exactly on a surface (a patch's own sample point, a light sitting on a wall) is not
// blocked by that surface. epsilon() = 1e-5 x sceneExtent(); see ray_caster.cpp for why,
// and for the centred frame that keeps it valid for scenes far from the origin.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "geometry/types.h"
#include "scene/scene.h"

namespace radbake {

// One triangle of the scene: Scene::meshes[mesh].triangles[triangle].
struct TriangleRef {
    uint32_t mesh = 0;
    uint32_t triangle = 0;
};

// The opaque triangle that blocks a ray (transmittanceAndBlockersFrom).
struct RayBlocker {
    bool found = false;
    uint32_t mesh = 0;
    uint32_t polygon = 0;  // the mesh's source polygon holding the triangle
    std::array<DVec3, 3> corners;  // world
};

// The first surface a ray meets (closestHit): hit point = (1 - u - v) * corner 0 + u * corner 1
// + v * corner 2 of the triangle, at distance t along the (normalised) direction.
struct RayHit {
    TriangleRef triangle;
    double t = 0.0;
    double u = 0.0, v = 0.0;
};

class RayCaster {
public:
    // Builds the acceleration structure (robust, high quality). Returns nullptr after an error
    // reported to `diagnostics` (Embree's device or build errors); never throws. Triangles with
    // out-of-range indices or non-finite vertices are skipped with a warning. `threads` caps
    // the threads Embree builds with (0: all cores), in an arena of its own (no process-wide
    // limit is set); queries run on the caller's threads. The structure's answers do not depend on it.
    static std::unique_ptr<RayCaster> build(const Scene& scene, Diagnostics& diagnostics, int threads = 0);
    ~RayCaster();
    RayCaster(const RayCaster&) = delete;
    RayCaster& operator=(const RayCaster&) = delete;

    double sceneExtent() const;  // the scene's bounding-box diagonal (0 for an empty scene)
    Aabb sceneBounds() const;    // bounding box of the usable triangles (empty() for none)
    double epsilon() const;      // the end offset applied to every segment, scene units
    size_t triangleCount() const;  // triangles in the structure

    // True when some opaque triangle crosses the segment strictly between from and to, both ends
    // shortened by epsilon(), or transmitting ones let nothing through. A segment shorter than
    // 2 epsilon() is never blocked.
    bool segmentBlocked(const DVec3& from, const DVec3& to) const;
    // The share of light that gets through the same segment: 0 blocked, 1 open, the product of
    // the transmittances (meshTransmittance) of the transmitting surfaces it crosses.
    double transmittance(const DVec3& from, const DVec3& to) const;

    // How many of the segments from -> to[k] are NOT blocked, each judged exactly as
    // segmentBlocked() judges it (same ends, same epsilon), cast as packets of 4 rays: a probe
    // casts a few segments from one point to each element it gathers from.
    size_t countOpenFrom(const DVec3& from, std::span<const DVec3> to) const;
    // The same, and the sum of weight[k] times their transmittance over the open segments in
    // `open_weight`.
    size_t countOpenFrom(const DVec3& from, std::span<const DVec3> to, std::span<const double> weight,
                         double& open_weight) const;

    // through[k] = transmittance(from, to[k]) (countOpenFrom's judgement, the same packets);
    // `through` holds to.size() entries.
    void transmittanceFrom(const DVec3& from, std::span<const DVec3> to, std::span<float> through) const;

    // Back twins (scene/two_sided.h) are not in the structure: their front blocks for both
    // sides. closestHit reports a hit on a two-sided front from behind as the back twin's
    // triangle of the same index (u and v swapped, as its corners 1 and 2 are).
    //
    // The nearest triangle (either face) hit by the ray origin + t * normalize(direction) with
    // t in [epsilon(), t_max] (the start is offset like a segment's, so a ray leaving a surface
    // does not hit it); nullopt on a miss, a zero or non-finite direction, or t_max < epsilon().
    // t is a distance in scene units. Embree intersects in float in the centred frame, so t
    // and (u, v) carry errors of a few 1e-7 x sceneExtent(); of two triangles sharing the
    // edge a ray crosses, either may be reported (but always the same one).
    std::optional<RayHit> closestHit(const DVec3& origin, const DVec3& direction, double t_max) const;

    // transmittanceFrom's answer for segments from `from` to far points to[k], and for each one
    // blocked, the first opaque triangle it meets (beyond any transmitting ones) in blockers[k].
    // Cast as packets of 4 intersection queries (more for those that cross transmitting
    // surfaces): what proves a cone of directions blocked (geometry/cone_cover.h) needs them.
    void transmittanceAndBlockersFrom(const DVec3& from, std::span<const DVec3> to, std::span<float> through,
                                      std::span<RayBlocker> blockers) const;

    // Appends the corners (world) of the triangles of source polygon `polygon` of `mesh`, when it
    // has at most `at_most` of them (else nothing): a blocker's whole face.
    void appendPolygonTriangles(uint32_t mesh, uint32_t polygon, size_t at_most,
                                std::vector<std::array<DVec3, 3>>& out) const;

    // Visible fraction in [0, 1] between two convex polygons (each segment counting its
    // transmittance) (vertices in order, 3 or more).
    // Each polygon gets n x n stratified points (n = samples_per_side; cell centres of a
    // grid mapped onto the polygon: bilinear on quads, area-preserving on triangles and other
    // convex polygons), and source stratum (i, j) is joined to receiver stratum
    // (i + j, i + 2j) mod n, a fixed bijection that keeps the pairs stratified (see
    // ray_caster.cpp); so n*n segments are cast. Fraction =
    // sum of their transmittances / n^2. rays_cast, when given, is INCREMENTED by the number of segments cast.
    double visibleFraction(std::span<const DVec3> source, std::span<const DVec3> receiver,
                           int samples_per_side, size_t* rays_cast = nullptr) const;

    // The same sample segments, tested only against the given candidate triangles with an
    // exact double-precision ray/triangle test (no Embree), for comparison with shaft
    // candidate lists: equals visibleFraction() when the candidates hold every triangle that
    // can block (up to the float/double precision difference at grazing hits).
    double visibleFractionAmong(std::span<const DVec3> source, std::span<const DVec3> receiver,
                                int samples_per_side, std::span<const TriangleRef> candidates,
                                size_t* rays_cast = nullptr) const;
    bool segmentBlockedAmong(const DVec3& from, const DVec3& to,
                             std::span<const TriangleRef> candidates) const;

    // Appends the triangles of a convex part (mesh part.mesh, source polygons part.polygons)
    // to `out`, to turn a list of candidate parts into a candidate triangle list.
    void appendPartTriangles(const ConvexPart& part, std::vector<TriangleRef>& out) const;

    // Embree errors raised after build() (during queries) are counted here and reported to
    // `diagnostics` by this call (single-threaded, e.g. at the end of a solve). Returns how many.
    size_t reportLateErrors(Diagnostics& diagnostics) const;

    struct Impl;

private:
    explicit RayCaster(std::unique_ptr<Impl> impl);
    // open(k) for every segment from -> to[k] that is not blocked (countOpenFrom's judgement).
    template <class Open>
    void forOpenFrom(const DVec3& from, std::span<const DVec3> to, Open&& open) const;
    std::unique_ptr<Impl> impl_;
};

// The n x n stratified sample points visibleFraction() uses on a convex polygon (exposed for
// the solver, which may want to evaluate other quantities at the same points, and for tests).
std::vector<DVec3> stratifiedPolygonPoints(std::span<const DVec3> polygon, int samples_per_side);

// The receiver point index that visibleFraction() joins to source point k (0 <= k < n*n).
size_t pairedSampleIndex(size_t k, int samples_per_side);

}  // namespace radbake
