// The Embree boundary: the only file in the project that includes Embree. Everything Embree
// reports goes to Diagnostics; nothing thrown here leaves this file.
#include "visibility/ray_caster.h"

#include "core/parallel.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <numeric>
#include <string>

namespace radbake {

namespace {

// closestHit's second query: every hit within a window around the first one's distance is
// recorded and rejected, so the whole tie set is seen whatever order Embree's traversal
// (which differs between SSE, AVX2 and AVX-512 builds) meets it in.
struct TieContext {
    RTCIntersectContext context;  // first: Embree passes a pointer to it to the filter
    bool collect = false;
    float t_lo = 0.0f, t_hi = 0.0f;
    struct Hit {
        unsigned geometry, primitive;
        float t, u, v;
    };
    std::array<Hit, 16> hits;
    size_t count = 0;
};

void collectTies(const RTCFilterFunctionNArguments* args) {
    const auto* base = args->context;
    if (base == nullptr || args->N != 1) return;
    auto* ties = const_cast<TieContext*>(reinterpret_cast<const TieContext*>(base));
    if (!ties->collect || args->valid[0] == 0) return;
    const float t = RTCRayN_tfar(args->ray, 1, 0);
    if (t >= ties->t_lo && t <= ties->t_hi && ties->count < ties->hits.size())
        ties->hits[ties->count++] = {RTCHitN_geomID(args->hit, 1, 0), RTCHitN_primID(args->hit, 1, 0), t,
                                     RTCHitN_u(args->hit, 1, 0), RTCHitN_v(args->hit, 1, 0)};
    args->valid[0] = 0;  // keep looking
}

// Occlusion queries cross transmitting surfaces (meshTransmittance > 0): their occlusion filter
// multiplies the lane's transmittance by the surface's and rejects the hit, so traversal goes
// on; the lane is blocked once its transmittance falls below kOpaqueBelow. Hits within `same` of
// a distance already passed are one crossing (the seam between two triangles of a pane, or
// between two panes, reports both), counted once.
constexpr float kOpaqueBelow = 1e-6f;
struct PassContext {
    RTCIntersectContext context;  // first: Embree passes a pointer to it to the filter
    const float* mesh_transmittance = nullptr;  // per geometry id
    float same = 0.0f;
    static constexpr int kLanes = 8;
    static constexpr int kRemembered = 8;
    std::array<float, kLanes> transmittance;
    std::array<std::array<float, kRemembered>, kLanes> passed_at;
    std::array<uint8_t, kLanes> passed{};

    PassContext(const float* per_mesh, double same_distance)
        : mesh_transmittance(per_mesh), same(static_cast<float>(same_distance)) {
        rtcInitIntersectContext(&context);
        transmittance.fill(1.0f);
    }
};

void passThrough(const RTCFilterFunctionNArguments* args) {
    auto* pass = const_cast<PassContext*>(reinterpret_cast<const PassContext*>(args->context));
    if (pass == nullptr || pass->mesh_transmittance == nullptr) return;
    for (unsigned i = 0; i < args->N && i < static_cast<unsigned>(PassContext::kLanes); ++i) {
        if (args->valid[i] == 0) continue;
        const float t = RTCRayN_tfar(args->ray, args->N, i);
        bool seen = false;
        for (uint8_t k = 0; k < pass->passed[i] && !seen; ++k) seen = std::abs(pass->passed_at[i][k] - t) <= pass->same;
        if (!seen) {
            if (pass->passed[i] < PassContext::kRemembered) pass->passed_at[i][pass->passed[i]++] = t;
            pass->transmittance[i] *= pass->mesh_transmittance[RTCHitN_geomID(args->hit, args->N, i)];
        }
        if (pass->transmittance[i] >= kOpaqueBelow) args->valid[i] = 0;  // through it: keep looking
    }
}

// Frame. Embree works in float; a scene far from the origin (georeferenced or CAD
// coordinates) would lose its float precision there. So Embree gets the geometry translated
// to the scene's bounding-box centre (computed in double from the stored floats, so nothing
// is lost), and every ray is translated the same way before it is rounded to float: rounding
// errors are then relative to the scene's extent, not to its distance from the origin.
//
// End offset, relative to the scene's extent (bounding-box diagonal D). In the centred frame
// coordinates are at most D/2, whose float spacing is 2^-24 D ~ 6e-8 D; a point that lies
// exactly on a surface comes out within a few such ulps of it after the rounding of the ray
// origin, and Embree's float intersection adds a few more. 1e-5 D is ~170 of those ulps:
// above that noise, and far below any feature a lighting bake resolves. (At grazing
// incidence, angle a to the surface, the offset along the ray keeps only 1e-5 D sin(a) from
// the surface, so an end point's own surface can still be hit below a ~ 0.3 degrees: the
// usual, accepted limit.)
constexpr double kRelativeEpsilon = 1e-5;
// Floor for a degenerate (empty or point-sized) scene, where any size-scaled value is 0.
constexpr double kMinEpsilon = 1e-30;

struct MeshCopy {
    std::vector<DVec3> positions;     // double copies for the exact candidate test
    std::vector<UVec3> triangles;     // as in the Scene
    std::vector<uint8_t> valid;       // triangle usable (indices in range, finite vertices)
    std::vector<uint32_t> polygon_start;  // CSR: triangles of polygon p are
    std::vector<uint32_t> polygon_triangles;  // polygon_triangles[polygon_start[p] .. polygon_start[p+1])
    std::vector<uint32_t> triangle_polygon;   // as in the Scene, when it has polygons
};

// A candidate triangle ready for the exact test: corner a and the two edges from it.
struct PreparedTriangle {
    DVec3 a, e1, e2;
};

}  // namespace

struct RayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<MeshCopy> meshes;
    // Per mesh: its back twin (scene/two_sided.h), kNoMesh when one-sided. A back twin is not
    // in the structure (it is its front's surface); closestHit names it for hits from behind.
    std::vector<uint32_t> back_twin;
    size_t triangle_count = 0;
    // Per mesh: the share of light its surfaces let through (0: opaque); empty when every mesh is.
    std::vector<float> mesh_transmittance;
    const float* passing() const { return mesh_transmittance.empty() ? nullptr : mesh_transmittance.data(); }
    PassContext passContext() const { return PassContext(passing(), epsilon); }
    Aabb bounds;
    DVec3 origin{0.0};  // Embree's frame: world minus origin (the bounds' centre)
    double extent = 0.0;
    double epsilon = kMinEpsilon;

    // Errors Embree raises. During build they are collected and moved to Diagnostics; after
    // build (queries on many threads) they are counted and kept for reportLateErrors().
    mutable std::mutex error_mutex;
    mutable std::vector<std::string> errors;
    mutable std::atomic<size_t> late_error_count{0};
    bool building = true;

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    void recordError(RTCError code, const char* text) {
        std::string message = "Embree error " + std::to_string(static_cast<int>(code));
        if (text && *text) message += std::string(": ") + text;
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!building) late_error_count.fetch_add(1, std::memory_order_relaxed);
        errors.push_back(std::move(message));
    }

    // The share of light that gets through the segment: 0 blocked, 1 open, between through
    // transmitting surfaces.
    double transmittance(const DVec3& from, const DVec3& to) const;
    // The sum over segments from[k] -> to[pairedIndex(k)] of their transmittance, cast in packets of 8.
    double countOpenPaired(const std::vector<DVec3>& from, const std::vector<DVec3>& to, size_t n) const;
    // The usable candidates, gathered once per query so the per-segment loop is contiguous.
    std::vector<PreparedTriangle> prepare(std::span<const TriangleRef> candidates) const;
    bool occludedAmong(const DVec3& from, const DVec3& to, std::span<const PreparedTriangle> triangles) const;

    // closestHit: Embree numbers a mesh's usable triangles 0..n-1, skipping unusable ones, so
    // a primitive id is mapped back to the mesh's triangle index. Built once, on first use
    // (thread-safe); a mesh whose triangles are all usable keeps an empty map (identity).
    mutable std::once_flag primitive_map_once;
    mutable std::vector<std::vector<uint32_t>> primitive_triangle;
    void buildPrimitiveMap() const;
    // Mesh `mesh`'s triangle index of Embree primitive `primitive` (after buildPrimitiveMap),
    // kNoMesh when out of range.
    uint32_t triangleOf(uint32_t mesh, uint32_t primitive) const {
        const std::vector<uint32_t>& map = primitive_triangle[mesh];
        const uint32_t triangle = map.empty() ? primitive : primitive < map.size() ? map[primitive] : kNoMesh;
        return triangle < meshes[mesh].triangles.size() ? triangle : kNoMesh;
    }
};

namespace {

void embreeErrorCallback(void* user, RTCError code, const char* text) {
    static_cast<RayCaster::Impl*>(user)->recordError(code, text);
}

// Lane `lane` of an Embree ray packet (RTCRay4 or RTCRay8) as the segment from `a` (relative to
// the scene's centred frame) along `delta`, both ends shortened by epsilon: the arithmetic of
// Impl::occluded(), so a segment gets the same answer in a packet as alone. An unused lane, or
// a segment too short (or not finite) to be blocked, is left invalid: false, counted as open.
template <typename Packet>
bool setSegmentLane(Packet& packet, int* valid, size_t lane, const DVec3& a, const DVec3& delta, double epsilon,
                    bool used) {
    valid[lane] = 0;
    packet.org_x[lane] = static_cast<float>(a.x);
    packet.org_y[lane] = static_cast<float>(a.y);
    packet.org_z[lane] = static_cast<float>(a.z);
    packet.dir_x[lane] = packet.dir_y[lane] = 0.0f;
    packet.dir_z[lane] = 1.0f;
    packet.tnear[lane] = 0.0f;
    packet.tfar[lane] = 0.0f;
    packet.time[lane] = 0.0f;
    packet.mask[lane] = 0xFFFFFFFFu;
    packet.id[lane] = static_cast<unsigned>(lane);
    packet.flags[lane] = 0;
    if (!used) return false;
    const double length = glm::length(delta);
    if (!(length > 2.0 * epsilon) || !std::isfinite(length)) return false;
    const DVec3 direction = delta / length;
    valid[lane] = -1;
    packet.dir_x[lane] = static_cast<float>(direction.x);
    packet.dir_y[lane] = static_cast<float>(direction.y);
    packet.dir_z[lane] = static_cast<float>(direction.z);
    packet.tnear[lane] = static_cast<float>(epsilon);
    packet.tfar[lane] = static_cast<float>(length - epsilon);
    return true;
}

bool usableTriangle(const Mesh& mesh, const UVec3& t) {
    const size_t n = mesh.positions.size();
    if (t.x >= n || t.y >= n || t.z >= n) return false;
    return isFinite(mesh.positions[t.x]) && isFinite(mesh.positions[t.y]) && isFinite(mesh.positions[t.z]);
}

// Copies a mesh for the exact test and indexes its polygons' triangles (CSR), without
// trusting triangle_polygon to be contiguous or complete.
MeshCopy copyMesh(const Mesh& mesh, size_t& skipped) {
    MeshCopy copy;
    copy.positions.assign(mesh.positions.begin(), mesh.positions.end());
    copy.triangles = mesh.triangles;
    copy.valid.resize(mesh.triangles.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        copy.valid[t] = usableTriangle(mesh, mesh.triangles[t]) ? 1 : 0;
        if (!copy.valid[t]) ++skipped;
    }
    const bool has_polygons = mesh.triangle_polygon.size() == mesh.triangles.size();
    const uint32_t polygon_count = has_polygons ? mesh.polygon_count : 0;
    copy.polygon_start.assign(polygon_count + 1, 0);
    if (has_polygons) {
        for (uint32_t p : mesh.triangle_polygon)
            if (p < polygon_count) ++copy.polygon_start[p + 1];
        std::partial_sum(copy.polygon_start.begin(), copy.polygon_start.end(), copy.polygon_start.begin());
        copy.polygon_triangles.resize(copy.polygon_start.back());
        std::vector<uint32_t> fill(copy.polygon_start.begin(), copy.polygon_start.end() - 1);
        for (uint32_t t = 0; t < mesh.triangle_polygon.size(); ++t) {
            const uint32_t p = mesh.triangle_polygon[t];
            if (p < polygon_count) copy.polygon_triangles[fill[p]++] = t;
        }
        copy.triangle_polygon = mesh.triangle_polygon;
    }
    return copy;
}

// Exact segment/triangle test in double (Moller-Trumbore), hits with t in (t_min, t_max)
// along a unit direction. Both faces count: visibility ignores orientation.
bool segmentHitsTriangle(const DVec3& origin, const DVec3& direction, double t_min, double t_max,
                         const PreparedTriangle& triangle) {
    const DVec3& a = triangle.a;
    const DVec3& e1 = triangle.e1;
    const DVec3& e2 = triangle.e2;
    const DVec3 p = glm::cross(direction, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0 || !std::isfinite(det)) return false;  // parallel or degenerate
    const double inv_det = 1.0 / det;
    const DVec3 s = origin - a;
    const double u = glm::dot(s, p) * inv_det;
    if (u < 0.0 || u > 1.0) return false;
    const DVec3 q = glm::cross(s, e1);
    const double v = glm::dot(direction, q) * inv_det;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = glm::dot(e2, q) * inv_det;
    return t > t_min && t < t_max;
}

// Maps a point (u, v) of the unit square onto a triangle, preserving area (so equal strata of
// the square become equal-area strata of the triangle).
DVec3 squareToTriangle(double u, double v, const DVec3& a, const DVec3& b, const DVec3& c) {
    const double s = std::sqrt(u);
    return (1.0 - s) * a + s * (1.0 - v) * b + s * v * c;
}

// The receiver stratum joined to source stratum (i, j) of an n x n grid:
// (i + j, i + 2j) mod n. A bijection (determinant 1), so every receiver point is used exactly
// once; and for fixed i or fixed j each receiver coordinate is itself a permutation, so the
// projections (u_s, u_r), (v_s, u_r) and (v_s, v_r) are full n x n grids: an occluder edge
// parallel to either quad edge sees stratified, not random, pairs. For odd n the remaining
// projection (u_s, v_r) is a full grid too (orthogonal Latin squares); for even n it covers
// every other stratum.
size_t pairedIndex(size_t k, size_t n) {
    const size_t i = k / n, j = k % n;
    return ((i + j) % n) * n + (i + 2 * j) % n;
}

}  // namespace

size_t pairedSampleIndex(size_t k, int samples_per_side) {
    return pairedIndex(k, static_cast<size_t>(std::max(samples_per_side, 1)));
}

std::vector<DVec3> stratifiedPolygonPoints(std::span<const DVec3> polygon, int samples_per_side) {
    const int n = std::max(samples_per_side, 1);
    std::vector<DVec3> points;
    points.reserve(static_cast<size_t>(n) * n);
    if (polygon.empty()) return points;
    const size_t m = polygon.size();
    // Fan triangles' cumulative areas for the general (and triangle) case.
    std::vector<double> cumulative;
    if (m != 4 && m >= 3) {
        cumulative.reserve(m - 2);
        double total = 0.0;
        for (size_t i = 1; i + 1 < m; ++i) {
            total += 0.5 * glm::length(glm::cross(polygon[i] - polygon[0], polygon[i + 1] - polygon[0]));
            cumulative.push_back(total);
        }
    }
    for (int i = 0; i < n; ++i) {
        const double u = (i + 0.5) / n;
        for (int j = 0; j < n; ++j) {
            const double v = (j + 0.5) / n;
            if (m == 1) {
                points.push_back(polygon[0]);
            } else if (m == 2) {
                points.push_back(polygon[0] + u * (polygon[1] - polygon[0]));
            } else if (m == 4) {  // bilinear: strata follow the quad's edges
                points.push_back((1 - u) * (1 - v) * polygon[0] + u * (1 - v) * polygon[1] + u * v * polygon[2] +
                                 (1 - u) * v * polygon[3]);
            } else {
                const double total = cumulative.back();
                if (!(total > 0.0)) {  // degenerate polygon: fall back to its first edge
                    points.push_back(polygon[0] + u * (polygon[1] - polygon[0]));
                    continue;
                }
                const double target = u * total;
                size_t t = std::lower_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin();
                t = std::min(t, cumulative.size() - 1);
                const double before = t == 0 ? 0.0 : cumulative[t - 1];
                const double area = cumulative[t] - before;
                const double local_u = area > 0.0 ? std::clamp((target - before) / area, 0.0, 1.0) : 0.5;
                points.push_back(squareToTriangle(local_u, v, polygon[0], polygon[t + 1], polygon[t + 2]));
            }
        }
    }
    return points;
}

double RayCaster::Impl::transmittance(const DVec3& from, const DVec3& to) const {
    const DVec3 delta = to - from;
    const double length = glm::length(delta);
    if (!(length > 2.0 * epsilon) || !std::isfinite(length)) return 1.0;
    const DVec3 direction = delta / length;
    PassContext pass = passContext();
    RTCRay ray{};
    const DVec3 from_local = from - origin;
    ray.org_x = static_cast<float>(from_local.x);
    ray.org_y = static_cast<float>(from_local.y);
    ray.org_z = static_cast<float>(from_local.z);
    ray.dir_x = static_cast<float>(direction.x);
    ray.dir_y = static_cast<float>(direction.y);
    ray.dir_z = static_cast<float>(direction.z);
    ray.tnear = static_cast<float>(epsilon);
    ray.tfar = static_cast<float>(length - epsilon);
    ray.mask = 0xFFFFFFFFu;
    ray.flags = 0;
    ray.time = 0.0f;
    rtcOccluded1(scene, &pass.context, &ray);
    return ray.tfar == -std::numeric_limits<float>::infinity() ? 0.0 : double(pass.transmittance[0]);
}

double RayCaster::Impl::countOpenPaired(const std::vector<DVec3>& from, const std::vector<DVec3>& to,
                                        size_t n) const {
    constexpr size_t kLanes = 8;
    double open = 0.0;
    for (size_t first = 0; first < from.size(); first += kLanes) {
        // The segments of one element pair are coherent (they join two small polygons).
        PassContext pass = passContext();
        pass.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        RTCRay8 packet;
        alignas(32) int valid[kLanes];
        for (size_t lane = 0; lane < kLanes; ++lane) {
            const size_t k = first + lane;
            const bool used = k < from.size();
            const DVec3 a = used ? from[k] - origin : DVec3(0.0);
            const DVec3 delta = used ? to[pairedIndex(k, n)] - from[k] : DVec3(0.0);
            if (!setSegmentLane(packet, valid, lane, a, delta, epsilon, used) && used) open += 1.0;
        }
        rtcOccluded8(valid, scene, &pass.context, &packet);
        for (size_t lane = 0; lane < kLanes; ++lane)
            if (valid[lane] && packet.tfar[lane] != -std::numeric_limits<float>::infinity())
                open += pass.transmittance[lane];
    }
    return open;
}

std::vector<PreparedTriangle> RayCaster::Impl::prepare(std::span<const TriangleRef> candidates) const {
    std::vector<PreparedTriangle> out;
    out.reserve(candidates.size());
    for (const TriangleRef& ref : candidates) {
        if (ref.mesh >= meshes.size()) continue;
        const MeshCopy& mesh = meshes[ref.mesh];
        if (ref.triangle >= mesh.triangles.size() || !mesh.valid[ref.triangle]) continue;
        const UVec3 t = mesh.triangles[ref.triangle];
        const DVec3& a = mesh.positions[t.x];
        out.push_back({a, mesh.positions[t.y] - a, mesh.positions[t.z] - a});
    }
    return out;
}

bool RayCaster::Impl::occludedAmong(const DVec3& from, const DVec3& to,
                                    std::span<const PreparedTriangle> triangles) const {
    const DVec3 delta = to - from;
    const double length = glm::length(delta);
    if (!(length > 2.0 * epsilon) || !std::isfinite(length)) return false;
    const DVec3 direction = delta / length;
    for (const PreparedTriangle& triangle : triangles)
        if (segmentHitsTriangle(from, direction, epsilon, length - epsilon, triangle)) return true;
    return false;
}

namespace {

constexpr size_t kAttachFailed = static_cast<size_t>(-1);

// Gives Embree the usable triangles of one mesh, in the centred frame. Returns how many, or
// kAttachFailed (Embree has then reported why through the error callback).
size_t attachMesh(RayCaster::Impl& impl, const MeshCopy& copy, uint32_t geometry_id, bool transmits) {
    size_t valid_count = 0;
    for (uint8_t valid : copy.valid) valid_count += valid;
    if (valid_count == 0) return 0;
    RTCGeometry geometry = rtcNewGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geometry) return kAttachFailed;
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), copy.positions.size()));
    auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), valid_count));
    if (!vertices || !indices) {
        rtcReleaseGeometry(geometry);
        return kAttachFailed;
    }
    for (size_t v = 0; v < copy.positions.size(); ++v) {
        // Non-finite vertices are only referenced by skipped triangles; zero them so Embree
        // never sees them.
        const DVec3& p = copy.positions[v];
        const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        const DVec3 local = finite ? p - impl.origin : DVec3(0.0);
        vertices[3 * v + 0] = static_cast<float>(local.x);
        vertices[3 * v + 1] = static_cast<float>(local.y);
        vertices[3 * v + 2] = static_cast<float>(local.z);
    }
    size_t written = 0;
    for (size_t t = 0; t < copy.triangles.size(); ++t) {
        if (!copy.valid[t]) continue;
        indices[3 * written + 0] = copy.triangles[t].x;
        indices[3 * written + 1] = copy.triangles[t].y;
        indices[3 * written + 2] = copy.triangles[t].z;
        ++written;
    }
    rtcSetGeometryIntersectFilterFunction(geometry, collectTies);
    if (transmits) rtcSetGeometryOccludedFilterFunction(geometry, passThrough);
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(impl.scene, geometry, geometry_id);
    rtcReleaseGeometry(geometry);
    return valid_count;
}

}  // namespace

RayCaster::RayCaster(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RayCaster::~RayCaster() = default;

std::unique_ptr<RayCaster> RayCaster::build(const Scene& scene, Diagnostics& diagnostics, int threads) {
    const SourceLocation where{scene.source_path, 0, 0};
    try {
        auto impl = std::make_unique<Impl>();
        Impl* raw = impl.get();
        auto flushErrors = [&]() {
            std::lock_guard<std::mutex> lock(raw->error_mutex);
            for (std::string& message : raw->errors) diagnostics.error(where, "ray caster: " + message);
            const bool had = !raw->errors.empty();
            raw->errors.clear();
            return had;
        };

        // No "threads=N" in the device config: Embree turns it into a process-wide TBB limit
        // (tbb::global_control) that would bind the host program and every other bake. The
        // build runs in an arena of our own instead (below).
        // RADBAKE_EMBREE_CONFIG (e.g. "isa=sse4.2"): for tests that outputs are the same
        // whatever instruction set Embree picks on the machine.
        const char* config = std::getenv("RADBAKE_EMBREE_CONFIG");
        impl->device = rtcNewDevice(config != nullptr && *config != '\0' ? config : nullptr);
        if (!impl->device) {
            diagnostics.error(where, "ray caster: Embree device creation failed (error " +
                                         std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
            return nullptr;
        }
        rtcSetDeviceErrorFunction(impl->device, embreeErrorCallback, raw);
        impl->scene = rtcNewScene(impl->device);
        if (!impl->scene) {
            flushErrors();
            diagnostics.error(where, "ray caster: Embree scene creation failed");
            return nullptr;
        }
        // Robust traversal (no missed hits on shared edges) and the best BVH: the structure is
        // built once per bake and queried millions of times.
        rtcSetSceneFlags(impl->scene, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(impl->scene, RTC_BUILD_QUALITY_HIGH);

        // Pass 1: copies, usable triangles, bounds (which fix Embree's frame).
        size_t skipped = 0;
        Aabb bounds;
        impl->meshes.reserve(scene.meshes.size());
        for (const Mesh& mesh : scene.meshes) {
            impl->back_twin.push_back(!mesh.back && mesh.twin < scene.meshes.size() ? mesh.twin : kNoMesh);
            impl->meshes.push_back(mesh.back ? MeshCopy{} : copyMesh(mesh, skipped));
            const MeshCopy& copy = impl->meshes.back();
            for (size_t t = 0; t < copy.triangles.size(); ++t)
                if (copy.valid[t])
                    for (int k = 0; k < 3; ++k) bounds.add(copy.positions[copy.triangles[t][k]]);
        }
        impl->bounds = bounds;
        impl->origin = bounds.empty() ? DVec3(0.0) : bounds.center();
        impl->extent = bounds.empty() ? 0.0 : glm::length(bounds.extent());
        impl->epsilon = std::max(kMinEpsilon, kRelativeEpsilon * impl->extent);

        // Pass 2: one Embree geometry per mesh, geometry id = mesh index.
        for (const Mesh& mesh : scene.meshes)
            if (meshTransmittance(scene, mesh) > 0.0f) {
                impl->mesh_transmittance.resize(scene.meshes.size(), 0.0f);
                break;
            }
        for (uint32_t m = 0; m < impl->mesh_transmittance.size(); ++m)
            impl->mesh_transmittance[m] = meshTransmittance(scene, scene.meshes[m]);
        for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
            const bool transmits = !impl->mesh_transmittance.empty() && impl->mesh_transmittance[m] > 0.0f;
            const size_t added = attachMesh(*impl, impl->meshes[m], m, transmits);
            if (added == kAttachFailed) {
                flushErrors();
                diagnostics.error(where, "ray caster: Embree could not take mesh '" + scene.meshes[m].name + "'");
                return nullptr;
            }
            impl->triangle_count += added;
        }
        if (skipped > 0)
            diagnostics.warning(where, "ray caster: skipped " + std::to_string(skipped) +
                                           " triangle(s) with out-of-range indices or non-finite vertices");
        ParallelRunner(Threading{threads, false}).execute([&] { rtcCommitScene(impl->scene); });
        if (flushErrors()) return nullptr;

        {
            std::lock_guard<std::mutex> lock(impl->error_mutex);
            impl->building = false;
        }
        return std::unique_ptr<RayCaster>(new RayCaster(std::move(impl)));
    } catch (const std::exception& e) {
        diagnostics.error(where, std::string("ray caster: ") + e.what());
    } catch (...) {
        diagnostics.error(where, "ray caster: unknown failure while building");
    }
    return nullptr;
}

double RayCaster::sceneExtent() const { return impl_->extent; }
Aabb RayCaster::sceneBounds() const { return impl_->bounds; }
double RayCaster::epsilon() const { return impl_->epsilon; }
size_t RayCaster::triangleCount() const { return impl_->triangle_count; }

bool RayCaster::segmentBlocked(const DVec3& from, const DVec3& to) const {
    return impl_->transmittance(from, to) == 0.0;
}

double RayCaster::transmittance(const DVec3& from, const DVec3& to) const { return impl_->transmittance(from, to); }

template <class Open>
void RayCaster::forOpenFrom(const DVec3& from, std::span<const DVec3> to, Open&& open) const {
    constexpr size_t kLanes = 4;
    const Impl& impl = *impl_;
    const DVec3 from_local = from - impl.origin;
    for (size_t first = 0; first < to.size(); first += kLanes) {
        PassContext pass = impl.passContext();
        RTCRay4 packet;
        alignas(16) int valid[kLanes];
        for (size_t lane = 0; lane < kLanes; ++lane) {
            const size_t k = first + lane;
            const bool used = k < to.size();
            const DVec3 delta = used ? to[k] - from : DVec3(0.0);
            if (!setSegmentLane(packet, valid, lane, from_local, delta, impl.epsilon, used) && used) open(k, 1.0);
        }
        rtcOccluded4(valid, impl.scene, &pass.context, &packet);
        for (size_t lane = 0; lane < kLanes; ++lane)
            if (valid[lane] && packet.tfar[lane] != -std::numeric_limits<float>::infinity())
                open(first + lane, double(pass.transmittance[lane]));
    }
}

size_t RayCaster::countOpenFrom(const DVec3& from, std::span<const DVec3> to) const {
    size_t open = 0;
    forOpenFrom(from, to, [&](size_t, double) { ++open; });
    return open;
}

void RayCaster::transmittanceFrom(const DVec3& from, std::span<const DVec3> to, std::span<float> through) const {
    std::fill(through.begin(), through.end(), 0.0f);
    forOpenFrom(from, to, [&](size_t k, double t) { through[k] = static_cast<float>(t); });
}

size_t RayCaster::countOpenFrom(const DVec3& from, std::span<const DVec3> to, std::span<const double> weight,
                                double& open_weight) const {
    size_t open = 0;
    open_weight = 0.0;
    forOpenFrom(from, to, [&](size_t k, double through) {
        ++open;
        open_weight += weight[k] * through;
    });
    return open;
}

bool RayCaster::segmentBlockedAmong(const DVec3& from, const DVec3& to,
                                    std::span<const TriangleRef> candidates) const {
    return impl_->occludedAmong(from, to, impl_->prepare(candidates));
}

namespace {

template <class Blocked>
double sampledFraction(std::span<const DVec3> source, std::span<const DVec3> receiver, int samples_per_side,
                       size_t* rays_cast, Blocked&& blocked) {
    if (source.empty() || receiver.empty()) return 0.0;
    const std::vector<DVec3> from = stratifiedPolygonPoints(source, samples_per_side);
    const std::vector<DVec3> to = stratifiedPolygonPoints(receiver, samples_per_side);
    const size_t n = static_cast<size_t>(std::max(samples_per_side, 1));
    size_t open = 0;
    for (size_t k = 0; k < from.size(); ++k)
        if (!blocked(from[k], to[pairedIndex(k, n)])) ++open;
    if (rays_cast) *rays_cast += from.size();
    return static_cast<double>(open) / static_cast<double>(from.size());
}

}  // namespace

double RayCaster::visibleFraction(std::span<const DVec3> source, std::span<const DVec3> receiver,
                                  int samples_per_side, size_t* rays_cast) const {
    if (source.empty() || receiver.empty()) return 0.0;
    const std::vector<DVec3> from = stratifiedPolygonPoints(source, samples_per_side);
    const std::vector<DVec3> to = stratifiedPolygonPoints(receiver, samples_per_side);
    const double open = impl_->countOpenPaired(from, to, static_cast<size_t>(std::max(samples_per_side, 1)));
    if (rays_cast) *rays_cast += from.size();
    return open / static_cast<double>(from.size());
}

double RayCaster::visibleFractionAmong(std::span<const DVec3> source, std::span<const DVec3> receiver,
                                       int samples_per_side, std::span<const TriangleRef> candidates,
                                       size_t* rays_cast) const {
    const std::vector<PreparedTriangle> triangles = impl_->prepare(candidates);
    return sampledFraction(source, receiver, samples_per_side, rays_cast, [&](const DVec3& a, const DVec3& b) {
        return impl_->occludedAmong(a, b, triangles);
    });
}

void RayCaster::appendPartTriangles(const ConvexPart& part, std::vector<TriangleRef>& out) const {
    if (part.mesh >= impl_->meshes.size()) return;
    const MeshCopy& mesh = impl_->meshes[part.mesh];
    const size_t polygon_count = mesh.polygon_start.empty() ? 0 : mesh.polygon_start.size() - 1;
    for (uint32_t p : part.polygons) {
        if (p >= polygon_count) continue;
        for (uint32_t i = mesh.polygon_start[p]; i < mesh.polygon_start[p + 1]; ++i)
            out.push_back({part.mesh, mesh.polygon_triangles[i]});
    }
}

void RayCaster::Impl::buildPrimitiveMap() const {
    primitive_triangle.assign(meshes.size(), {});
    for (size_t m = 0; m < meshes.size(); ++m) {
        const MeshCopy& mesh = meshes[m];
        if (std::all_of(mesh.valid.begin(), mesh.valid.end(), [](uint8_t v) { return v != 0; })) continue;
        for (uint32_t t = 0; t < mesh.valid.size(); ++t)
            if (mesh.valid[t]) primitive_triangle[m].push_back(t);
    }
}

namespace {

// One ray for rtcIntersect1 from `origin_local` (the centred frame) along unit `direction`
// over [t_near, t_far], no hit yet.
RTCRayHit rayHitQuery(const DVec3& origin_local, const DVec3& direction, float t_near, float t_far) {
    RTCRayHit query{};
    query.ray.org_x = static_cast<float>(origin_local.x);
    query.ray.org_y = static_cast<float>(origin_local.y);
    query.ray.org_z = static_cast<float>(origin_local.z);
    query.ray.dir_x = static_cast<float>(direction.x);
    query.ray.dir_y = static_cast<float>(direction.y);
    query.ray.dir_z = static_cast<float>(direction.z);
    query.ray.tnear = t_near;
    query.ray.tfar = t_far;
    query.ray.mask = 0xFFFFFFFFu;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    query.hit.primID = RTC_INVALID_GEOMETRY_ID;
    query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return query;
}

}  // namespace

std::optional<RayHit> RayCaster::closestHit(const DVec3& origin, const DVec3& direction, double t_max) const {
    const double length = glm::length(direction);
    if (!(length > 0.0) || !std::isfinite(length) || !(t_max >= impl_->epsilon)) return std::nullopt;
    const DVec3 unit = direction / length;
    const DVec3 origin_local = origin - impl_->origin;
    if (!std::isfinite(origin_local.x) || !std::isfinite(origin_local.y) || !std::isfinite(origin_local.z))
        return std::nullopt;
    std::call_once(impl_->primitive_map_once, [this] { impl_->buildPrimitiveMap(); });

    TieContext ties;
    rtcInitIntersectContext(&ties.context);
    // Beyond float range means unbounded.
    RTCRayHit query = rayHitQuery(origin_local, unit, static_cast<float>(impl_->epsilon),
                                  t_max < static_cast<double>(std::numeric_limits<float>::max())
                                      ? static_cast<float>(t_max)
                                      : std::numeric_limits<float>::infinity());
    rtcIntersect1(impl_->scene, &ties.context, &query);
    if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID || query.hit.geomID >= impl_->meshes.size()) return std::nullopt;
    // Surfaces at the same distance (coincident faces): the one with the least (geometry,
    // triangle) numbers, not the first one the traversal met.
    const float t_hit = query.ray.tfar;
    const float window = 4.0f * std::numeric_limits<float>::epsilon() *
                         (t_hit + std::abs(query.ray.org_x) + std::abs(query.ray.org_y) + std::abs(query.ray.org_z));
    ties.collect = true;
    ties.t_lo = t_hit - window;
    ties.t_hi = t_hit + window;
    query.ray.tnear = std::max(static_cast<float>(impl_->epsilon), ties.t_lo);
    query.ray.tfar = ties.t_hi;
    const unsigned first_geometry = query.hit.geomID, first_primitive = query.hit.primID;
    const float first_u = query.hit.u, first_v = query.hit.v;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &ties.context, &query);
    query.ray.tfar = t_hit;
    query.hit.geomID = first_geometry, query.hit.primID = first_primitive, query.hit.u = first_u, query.hit.v = first_v;
    for (size_t k = 0; k < ties.count; ++k) {
        const TieContext::Hit& h = ties.hits[k];
        if (h.geometry < query.hit.geomID || (h.geometry == query.hit.geomID && h.primitive < query.hit.primID)) {
            query.hit.geomID = h.geometry, query.hit.primID = h.primitive, query.hit.u = h.u, query.hit.v = h.v;
            query.ray.tfar = h.t;
        }
    }
    if (query.hit.geomID >= impl_->meshes.size()) return std::nullopt;

    const uint32_t mesh = query.hit.geomID;
    const uint32_t triangle = impl_->triangleOf(mesh, query.hit.primID);
    if (triangle == kNoMesh) return std::nullopt;
    const MeshCopy& copy = impl_->meshes[mesh];
    RayHit hit;
    hit.triangle = {mesh, triangle};
    hit.t = static_cast<double>(query.ray.tfar);
    hit.u = static_cast<double>(query.hit.u);
    hit.v = static_cast<double>(query.hit.v);
    const uint32_t back = impl_->back_twin[mesh];
    if (back != kNoMesh) {
        const UVec3& tri = copy.triangles[triangle];
        const DVec3& a = copy.positions[tri.x];
        const DVec3 normal = glm::cross(copy.positions[tri.y] - a, copy.positions[tri.z] - a);
        if (glm::dot(normal, unit) > 0.0) {  // seen from behind: the back twin's triangle t, corners 1 and 2 swapped
            hit.triangle.mesh = back;
            std::swap(hit.u, hit.v);
        }
    }
    return hit;
}

namespace {

// A single intersection query from `origin_local` (the centred frame) along unit `direction` over
// [t_near, t_far]: the mesh and primitive met first, or false.
bool firstHit(RTCScene scene, const DVec3& origin_local, const DVec3& direction, float t_near, float t_far,
              unsigned& mesh, unsigned& primitive, float& t) {
    TieContext ties;  // collect stays false: the geometries' intersect filter lets every hit stand
    rtcInitIntersectContext(&ties.context);
    RTCRayHit query = rayHitQuery(origin_local, direction, t_near, t_far);
    rtcIntersect1(scene, &ties.context, &query);
    if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    mesh = query.hit.geomID, primitive = query.hit.primID, t = query.ray.tfar;
    return true;
}

}  // namespace

void RayCaster::transmittanceAndBlockersFrom(const DVec3& from, std::span<const DVec3> to, std::span<float> through,
                                             std::span<RayBlocker> blockers) const {
    constexpr size_t kLanes = 4;
    const Impl& impl = *impl_;
    std::call_once(impl.primitive_map_once, [this] { impl_->buildPrimitiveMap(); });
    const DVec3 from_local = from - impl.origin;
    std::fill(through.begin(), through.end(), 1.0f);
    auto transmits = [&](unsigned mesh) { return !impl.mesh_transmittance.empty() && impl.mesh_transmittance[mesh] > 0.0f; };
    auto record = [&](size_t k, unsigned mesh, unsigned primitive) {
        RayBlocker& blocker = blockers[k];
        blocker.found = false;
        if (mesh >= impl.meshes.size()) return;
        const uint32_t triangle = impl.triangleOf(mesh, primitive);
        if (triangle == kNoMesh) return;
        const MeshCopy& copy = impl.meshes[mesh];
        const UVec3& t = copy.triangles[triangle];
        const uint32_t polygon = triangle < copy.triangle_polygon.size() ? copy.triangle_polygon[triangle] : kNoMesh;
        blocker = {true, mesh, polygon, {copy.positions[t.x], copy.positions[t.y], copy.positions[t.z]}};
    };
    std::vector<size_t> transmitting;  // first met a transmitting surface
    for (size_t first = 0; first < to.size(); first += kLanes) {
        TieContext ties;
        rtcInitIntersectContext(&ties.context);
        RTCRayHit4 packet;
        alignas(16) int valid[kLanes];
        for (size_t lane = 0; lane < kLanes; ++lane) {
            const size_t k = first + lane;
            const bool used = k < to.size();
            if (used) blockers[k].found = false;
            setSegmentLane(packet.ray, valid, lane, from_local, used ? to[k] - from : DVec3(0.0), impl.epsilon, used);
            packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
            packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect4(valid, impl.scene, &ties.context, &packet);
        for (size_t lane = 0; lane < kLanes; ++lane) {
            const size_t k = first + lane;
            const unsigned mesh = packet.hit.geomID[lane];
            if (k >= to.size() || !valid[lane] || mesh >= impl.meshes.size()) continue;
            if (transmits(mesh)) {
                transmitting.push_back(k);
                continue;
            }
            through[k] = 0.0f;
            record(k, mesh, packet.hit.primID[lane]);
        }
    }
    if (transmitting.empty()) return;
    std::vector<DVec3> far(transmitting.size());
    std::vector<float> passed(transmitting.size());
    for (size_t i = 0; i < transmitting.size(); ++i) far[i] = to[transmitting[i]];
    transmittanceFrom(from, far, passed);
    for (size_t i = 0; i < transmitting.size(); ++i) {
        const size_t k = transmitting[i];
        through[k] = passed[i];
        if (passed[i] != 0.0f) continue;
        // Blocked behind the glass: the first opaque surface past the transmitting ones.
        const DVec3 delta = to[k] - from;
        const double length = glm::length(delta);
        const DVec3 direction = delta / length;
        float t_near = static_cast<float>(impl.epsilon);
        for (int crossing = 0; crossing < 16; ++crossing) {
            unsigned mesh = 0, primitive = 0;
            float t = 0.0f;
            if (!firstHit(impl.scene, from_local, direction, t_near, static_cast<float>(length - impl.epsilon), mesh,
                          primitive, t))
                break;
            if (!transmits(mesh)) {
                record(k, mesh, primitive);
                break;
            }
            t_near = t + static_cast<float>(impl.epsilon);
        }
    }
}

void RayCaster::appendPolygonTriangles(uint32_t mesh, uint32_t polygon, size_t at_most,
                                       std::vector<std::array<DVec3, 3>>& out) const {
    if (mesh >= impl_->meshes.size()) return;
    const MeshCopy& copy = impl_->meshes[mesh];
    if (polygon + 1 >= copy.polygon_start.size()) return;
    const uint32_t begin = copy.polygon_start[polygon], end = copy.polygon_start[polygon + 1];
    if (end - begin > at_most) return;
    for (uint32_t i = begin; i < end; ++i) {
        const uint32_t triangle = copy.polygon_triangles[i];
        if (!copy.valid[triangle]) continue;
        const UVec3& t = copy.triangles[triangle];
        out.push_back({copy.positions[t.x], copy.positions[t.y], copy.positions[t.z]});
    }
}

size_t RayCaster::reportLateErrors(Diagnostics& diagnostics) const {
    std::lock_guard<std::mutex> lock(impl_->error_mutex);
    const size_t count = impl_->late_error_count.exchange(0);
    for (std::string& message : impl_->errors) diagnostics.error({}, "ray caster: " + message);
    impl_->errors.clear();
    return count;
}

}  // namespace radbake
