// Charts: coplanar connected triangles of a mesh, grown from a seed triangle across shared
// edges, then across smooth edges (below the mesh's crease angle) within a cone of the
// seed's normal and without overlap, projected onto the seed's plane and cut along a
// texel-aligned grid when larger than the cap.
#include "bake/lightmap_charts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

namespace radbake {
namespace {

// Tolerances scale with the scene's extent (bounding-box diagonal):
// - vertices closer than kWeld * extent are one vertex for connectivity (float positions
//   carry ~1e-7 relative rounding, transforms a little more);
// - a triangle is coplanar with a chart when its normal is within ~0.8 degrees of the
//   seed's (1 - cos = kNormal) and its corners are within kPlane * extent of the plane;
// - triangles with area below kDegenerate * extent^2 are dropped (no texel can see them).
constexpr double kWeld = kLightmapWeld;
constexpr double kNormal = 1e-4;
constexpr double kPlane = 1e-5;
constexpr double kDegenerate = 1e-14;
// Projected triangles of one chart may touch, or overlap by rounding (kOverlap * extent), but
// not more: two faces on one texel would fight over it.
constexpr double kOverlap = 1e-7;
// A face joins a chart across a smooth edge (dihedral angle below the mesh's crease angle)
// only while its normal stays within 35 degrees of the chart's projection normal: its texels
// are then stretched by at most 1 / cos(35 deg) = 1.22 (a texel covers at most 22 % more
// surface than on the seed face), so resolution stays even over a curved surface. Wider cones
// bend charts further round and stretch more; narrower ones make more charts and seams.
constexpr double kChartConeDegrees = 35.0;
constexpr double kNearlyFlatDegrees = 5.0;
const double kChartConeCos = std::cos(kChartConeDegrees * kPi / 180.0);

}  // namespace

double lightmapExtent(const Scene& scene) {
    DVec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Mesh& mesh : scene.meshes)
        for (const Vec3& p : mesh.positions) {
            lo = glm::min(lo, DVec3(p));
            hi = glm::max(hi, DVec3(p));
        }
    return hi.x >= lo.x ? std::max(glm::length(hi - lo), 1e-9) : 1.0;
}

// Welded vertex ids: positions quantised to cells of `weld` share an id.
std::vector<uint32_t> weldLightmapVertices(const Mesh& mesh, double weld) {
    std::map<std::array<int64_t, 3>, uint32_t> ids;
    std::vector<uint32_t> welded(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        const DVec3 q = glm::floor(DVec3(mesh.positions[v]) / weld + 0.5);
        const std::array<int64_t, 3> key{static_cast<int64_t>(q.x), static_cast<int64_t>(q.y), static_cast<int64_t>(q.z)};
        welded[v] = ids.emplace(key, static_cast<uint32_t>(ids.size())).first->second;
    }
    return welded;
}

namespace {

uint64_t edgeKey(uint32_t a, uint32_t b) {
    if (a > b) std::swap(a, b);
    return (uint64_t{a} << 32) | b;
}

struct TriangleInfo {
    std::array<DVec3, 3> p;
    DVec3 normal{0.0};
    bool degenerate = true;
};

// The world axis most parallel to the plane, made orthogonal to the normal: walls and
// floors get texel rows along world axes, so their charts are tight rectangles.
void planeFrame(LightmapChart& chart, const DVec3& normal, const DVec3& origin) {
    int k = 0;
    for (int i = 1; i < 3; ++i)
        if (std::fabs(normal[i]) < std::fabs(normal[k])) k = i;
    DVec3 axis(0.0);
    axis[k] = 1.0;
    chart.normal_world = normal;
    chart.u_world = glm::normalize(axis - normal * glm::dot(normal, axis));
    chart.v_world = glm::cross(normal, chart.u_world);
    chart.origin_world = origin;
}

DVec2 toPlane(const LightmapChart& chart, const DVec3& p_world) {
    const DVec3 d = p_world - chart.origin_world;
    return DVec2(glm::dot(d, chart.u_world), glm::dot(d, chart.v_world));
}

struct ProjectedTriangle {
    std::array<DVec2, 3> p;
    DVec2 lo{0.0}, hi{0.0};
    double twice_area = 0.0;  // signed: positive when it faces the chart's normal
};

ProjectedTriangle project(const LightmapChart& chart, const TriangleInfo& triangle) {
    ProjectedTriangle out;
    for (int k = 0; k < 3; ++k) out.p[k] = toPlane(chart, triangle.p[k]);
    out.lo = glm::min(out.p[0], glm::min(out.p[1], out.p[2]));
    out.hi = glm::max(out.p[0], glm::max(out.p[1], out.p[2]));
    const DVec2 e1 = out.p[1] - out.p[0], e2 = out.p[2] - out.p[0];
    out.twice_area = e1.x * e2.y - e1.y * e2.x;
    return out;
}

// True when the interiors of two projected triangles overlap by more than `slack` (separating
// axes: the six edge normals). Triangles sharing an edge or a vertex only touch.
bool projectedOverlap(const ProjectedTriangle& a, const ProjectedTriangle& b, double slack) {
    if (a.hi.x <= b.lo.x + slack || b.hi.x <= a.lo.x + slack || a.hi.y <= b.lo.y + slack || b.hi.y <= a.lo.y + slack)
        return false;
    for (const ProjectedTriangle* t : {&a, &b})
        for (int k = 0; k < 3; ++k) {
            const DVec2 e = t->p[(k + 1) % 3] - t->p[k];
            const double length = glm::length(e);
            if (!(length > 0.0)) continue;
            const DVec2 axis(-e.y / length, e.x / length);
            double a_lo = glm::dot(a.p[0], axis), a_hi = a_lo, b_lo = glm::dot(b.p[0], axis), b_hi = b_lo;
            for (int i = 1; i < 3; ++i) {
                a_lo = std::min(a_lo, glm::dot(a.p[i], axis));
                a_hi = std::max(a_hi, glm::dot(a.p[i], axis));
                b_lo = std::min(b_lo, glm::dot(b.p[i], axis));
                b_hi = std::max(b_hi, glm::dot(b.p[i], axis));
            }
            if (a_hi <= b_lo + slack || b_hi <= a_lo + slack) return false;
        }
    return true;
}

// Sutherland-Hodgman against one axis-aligned half-plane: keep side * (p[axis] - bound) <= 0.
std::vector<DVec2> clipHalfPlane(const std::vector<DVec2>& polygon, int axis, double bound, double side) {
    std::vector<DVec2> out;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const DVec2& a = polygon[i];
        const DVec2& b = polygon[(i + 1) % polygon.size()];
        const double da = side * (a[axis] - bound), db = side * (b[axis] - bound);
        if (da <= 0.0) out.push_back(a);
        if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
            DVec2 crossing = a + (b - a) * (da / (da - db));
            crossing[axis] = bound;  // exactly on the cell edge
            out.push_back(crossing);
        }
    }
    return out;
}

// Texels needed for `metres` at the density; the small slack keeps an extent of exactly
// n texels (a cut cell) from rounding up to n + 1.
int texelsFor(double metres, const LightmapOptions& options) {
    const int n = static_cast<int>(std::ceil(metres * options.texels_per_metre - 1e-6));
    return std::max(n, std::max(options.min_chart_texels, 1));
}

void fitToFaces(LightmapChart& chart, const LightmapOptions& options) {
    DVec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    chart.area = 0.0;
    for (const ChartFace& face : chart.faces) {
        for (const DVec2& p : face.p_plane) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        chart.area += polygonArea(face.p_plane);
    }
    chart.min_plane = lo;
    chart.texels_per_metre = options.texels_per_metre;
    chart.width = texelsFor(hi.x - lo.x, options);
    chart.height = texelsFor(hi.y - lo.y, options);
}

// The texels a region takes at the density before any cap split, in double (a density
// far too high for the budget must not overflow an int or allocate anything): the split
// pieces are clipped to the faces, so together they take at most this.
double regionTexels(const LightmapChart& region, const LightmapOptions& options) {
    DVec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const ChartFace& face : region.faces)
        for (const DVec2& p : face.p_plane) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    const double floor = std::max(options.min_chart_texels, 1);
    const auto side = [&](double metres) { return std::max(std::ceil(metres * options.texels_per_metre - 1e-6), floor); };
    return side(hi.x - lo.x) * side(hi.y - lo.y);
}

// One region's chart, or its pieces on a grid of cap-sized cells when it exceeds the cap.
// With `estimate` set, only adds the region's texels to it (regionTexels) and builds nothing.
void emitCharts(LightmapChart region, int cap, double area_floor, const LightmapOptions& options,
                std::vector<LightmapChart>& charts, double* estimate) {
    if (estimate) {
        *estimate += regionTexels(region, options);
        return;
    }
    fitToFaces(region, options);
    if (region.width <= cap && region.height <= cap) {
        charts.push_back(std::move(region));
        return;
    }
    const double cell = cap / options.texels_per_metre;  // metres; cells align with the texel grid
    const int cells_u = (region.width + cap - 1) / cap, cells_v = (region.height + cap - 1) / cap;
    for (int j = 0; j < cells_v; ++j) {
        for (int i = 0; i < cells_u; ++i) {
            const DVec2 lo = region.min_plane + DVec2(i, j) * cell;
            LightmapChart piece = region;
            piece.faces.clear();
            for (const ChartFace& face : region.faces) {
                std::vector<DVec2> clipped = clipToRectangle(face.p_plane, lo, lo + DVec2(cell));
                if (clipped.empty() || !(polygonArea(clipped) > area_floor)) continue;
                ChartFace part = face;
                part.p_plane = std::move(clipped);
                piece.faces.push_back(std::move(part));
            }
            if (piece.faces.empty()) continue;
            fitToFaces(piece, options);
            piece.width = std::min(piece.width, cap);  // clipped to a cell: at most cap texels
            piece.height = std::min(piece.height, cap);
            charts.push_back(std::move(piece));
        }
    }
}

void meshCharts(const Scene& scene, uint32_t m, double extent, int cap, const LightmapOptions& options,
                std::vector<LightmapChart>& charts, double* estimate) {
    const Mesh& mesh = scene.meshes[m];
    const std::vector<uint32_t> welded = weldLightmapVertices(mesh, kWeld * extent);
    std::vector<TriangleInfo> info(mesh.triangles.size());
    std::unordered_map<uint64_t, std::vector<uint32_t>> edges;
    const double area_floor = kDegenerate * extent * extent;
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3& tri = mesh.triangles[t];
        if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() || tri.z >= mesh.positions.size()) continue;
        TriangleInfo& ti = info[t];
        for (int k = 0; k < 3; ++k) ti.p[k] = DVec3(mesh.positions[tri[k]]);
        const DVec3 cross = glm::cross(ti.p[1] - ti.p[0], ti.p[2] - ti.p[0]);
        const double twice_area = glm::length(cross);
        if (!(twice_area > 2.0 * area_floor)) continue;
        ti.normal = cross / twice_area;
        ti.degenerate = false;
        for (int k = 0; k < 3; ++k) edges[edgeKey(welded[tri[k]], welded[tri[(k + 1) % 3]])].push_back(t);
    }

    std::vector<bool> assigned(mesh.triangles.size(), false);
    // Edges bent less than kNearlyFlatDegrees join charts even at crease angle 0: measured
    // or hand-modelled walls are rarely exactly planar (the Cornell Box's walls bend by a
    // fraction of a degree along their diagonals), and a chart per triangle would put a seam
    // across every such wall. Each face keeps its own normal for its texels.
    const double cos_crease =
        std::cos(std::max(static_cast<double>(mesh.crease_angle), kNearlyFlatDegrees * kPi / 180.0));
    const bool smooth_edges = true;
    for (uint32_t seed = 0; seed < mesh.triangles.size(); ++seed) {
        if (assigned[seed] || info[seed].degenerate) continue;
        const DVec3 normal = info[seed].normal;
        const double offset = glm::dot(normal, info[seed].p[0]);
        const auto coplanar = [&](uint32_t t) {
            if (glm::dot(info[t].normal, normal) < 1.0 - kNormal) return false;
            for (const DVec3& p : info[t].p)
                if (std::fabs(glm::dot(normal, p) - offset) > kPlane * extent) return false;
            return true;
        };
        LightmapChart region;
        region.mesh = m;
        region.material = mesh.material;
        planeFrame(region, normal, info[seed].p[0]);
        const auto neighbours = [&](uint32_t t, const auto& visit) {
            const UVec3& tri = mesh.triangles[t];
            for (int k = 0; k < 3; ++k)
                for (uint32_t n : edges[edgeKey(welded[tri[k]], welded[tri[(k + 1) % 3]])])
                    if (!assigned[n] && !info[n].degenerate) visit(n);
        };
        // First the coplanar connected region, as a flat chart (no overlap possible).
        std::vector<uint32_t> members{seed};
        assigned[seed] = true;
        for (size_t next = 0; next < members.size(); ++next)
            neighbours(members[next], [&](uint32_t n) {
                if (!coplanar(n)) return;
                assigned[n] = true;
                members.push_back(n);
            });
        // Then across smooth edges, breadth first (round charts), each face checked against the cone,
        // for flips and for overlap with every face already in.
        if (smooth_edges) {
            std::vector<ProjectedTriangle> projected;
            for (uint32_t t : members) projected.push_back(project(region, info[t]));
            for (size_t next = 0; next < members.size(); ++next) {
                const uint32_t t = members[next];
                neighbours(t, [&](uint32_t n) {
                    if (glm::dot(info[n].normal, info[t].normal) < cos_crease) return;  // a crease
                    if (glm::dot(info[n].normal, normal) < kChartConeCos) return;
                    const ProjectedTriangle candidate = project(region, info[n]);
                    if (!(candidate.twice_area > 0.0)) return;  // flipped or edge-on
                    for (const ProjectedTriangle& other : projected)
                        if (projectedOverlap(candidate, other, kOverlap * extent)) return;
                    assigned[n] = true;
                    members.push_back(n);
                    projected.push_back(candidate);
                });
            }
        }
        std::sort(members.begin(), members.end());  // faces in triangle order, whatever the walk
        for (uint32_t t : members) {
            ChartFace face;
            face.triangle = t;
            for (int k = 0; k < 3; ++k) {
                face.corner_world[k] = info[t].p[k];
                face.corner_plane[k] = toPlane(region, info[t].p[k]);
            }
            face.p_plane.assign(face.corner_plane.begin(), face.corner_plane.end());
            face.normal_world = info[t].normal;
            region.faces.push_back(std::move(face));
        }
        emitCharts(std::move(region), cap, area_floor, options, charts, estimate);
    }
}

}  // namespace

std::vector<DVec2> clipToRectangle(std::vector<DVec2> polygon, const DVec2& lo, const DVec2& hi) {
    for (int axis = 0; axis < 2 && polygon.size() >= 3; ++axis) {
        polygon = clipHalfPlane(polygon, axis, lo[axis], -1.0);
        if (polygon.size() >= 3) polygon = clipHalfPlane(polygon, axis, hi[axis], 1.0);
    }
    return polygon.size() >= 3 ? polygon : std::vector<DVec2>{};
}

double polygonArea(const std::vector<DVec2>& polygon) {
    double twice = 0.0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const DVec2& a = polygon[i];
        const DVec2& b = polygon[(i + 1) % polygon.size()];
        twice += a.x * b.y - a.y * b.x;
    }
    return 0.5 * twice;
}

namespace {

// The options mesh m's charts are built with: its density times its scale (the scale list
// left out, so the per-mesh copy is cheap).
LightmapOptions meshOptions(const LightmapOptions& base, const std::vector<double>& scales, uint32_t m) {
    LightmapOptions options = base;
    if (m < scales.size()) options.texels_per_metre *= scales[m];
    return options;
}

}  // namespace

std::vector<LightmapChart> buildLightmapCharts(const Scene& scene, const LightmapOptions& options) {
    std::vector<LightmapChart> charts;
    const double extent = lightmapExtent(scene);
    // A chart must fit an atlas with its padding on both sides.
    const int cap = std::max(1, std::min(options.max_chart_texels, options.atlas_size - 2 * options.padding));
    LightmapOptions base = options;
    base.mesh_texel_scale.clear();
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        meshCharts(scene, m, extent, cap, meshOptions(base, options.mesh_texel_scale, m), charts, nullptr);
    return charts;
}

double estimateLightmapTexels(const Scene& scene, const LightmapOptions& options) {
    std::vector<LightmapChart> none;
    double texels = 0.0;
    const double extent = lightmapExtent(scene);
    LightmapOptions base = options;
    base.mesh_texel_scale.clear();
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        meshCharts(scene, m, extent, 1, meshOptions(base, options.mesh_texel_scale, m), none, &texels);
    return texels;
}

}  // namespace radbake
