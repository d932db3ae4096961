#include "geometry/hull.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <unordered_map>

#include "geometry/polygon.h"

namespace radbake {

// ---------------------------------------------------------------------------------------
// 2D: Andrew's monotone chain.

namespace {

double cross2(const DVec2& o, const DVec2& a, const DVec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// True when `a` is not a strict left turn between o and b (within tolerance as a distance).
bool notLeft(const DVec2& o, const DVec2& a, const DVec2& b, double tolerance) {
    const double cross = cross2(o, a, b);
    if (tolerance == 0.0 || cross <= 0.0) return cross <= 0.0;
    return cross <= tolerance * glm::length(b - o);
}

}  // namespace

std::vector<uint32_t> convexHull2d(std::span<const DVec2> points, double tolerance) {
    // Sort copies (not indices) so the comparisons stay in cache.
    struct Item {
        DVec2 p;
        uint32_t index;
    };
    std::vector<Item> items(points.size());
    for (uint32_t i = 0; i < points.size(); ++i) items[i] = {points[i], i};
    std::sort(items.begin(), items.end(),
              [](const Item& a, const Item& b) { return a.p.x < b.p.x || (a.p.x == b.p.x && a.p.y < b.p.y); });
    // Duplicates (within tolerance) would create zero-length hull edges.
    std::vector<uint32_t> unique;
    unique.reserve(items.size());
    for (const Item& item : items)
        if (unique.empty() || glm::length(item.p - points[unique.back()]) > tolerance) unique.push_back(item.index);
    if (unique.size() <= 2) {
        if (unique.size() == 2 && glm::length(points[unique[0]] - points[unique[1]]) == 0.0) unique.pop_back();
        return unique;
    }
    std::vector<uint32_t> hull(2 * unique.size());
    size_t k = 0;
    for (uint32_t i : unique) {  // lower hull
        while (k >= 2 && notLeft(points[hull[k - 2]], points[hull[k - 1]], points[i], tolerance)) --k;
        hull[k++] = i;
    }
    for (size_t j = unique.size() - 1, lower = k + 1; j-- > 0;) {  // upper hull
        const uint32_t i = unique[j];
        while (k >= lower && notLeft(points[hull[k - 2]], points[hull[k - 1]], points[i], tolerance)) --k;
        hull[k++] = i;
    }
    hull.resize(k - 1);  // the last point repeats the first
    if (hull.size() < 3) {
        // All collinear: keep the two extremes.
        return {unique.front(), unique.back()};
    }
    return hull;
}

// ---------------------------------------------------------------------------------------
// Minimum-area rectangle by rotating calipers: one rectangle side is flush with a hull edge.

Rect2 minAreaRect(std::span<const DVec2> hull) {
    Rect2 best;
    const size_t n = hull.size();
    if (n == 0) return best;
    if (n == 1) {
        best.center = hull[0];
        return best;
    }
    if (n == 2) {
        const DVec2 d = hull[1] - hull[0];
        const double length = glm::length(d);
        best.center = 0.5 * (hull[0] + hull[1]);
        best.axis_u = length > 0.0 ? d / length : DVec2(1, 0);
        best.half_extents = DVec2(0.5 * length, 0.0);
        return best;
    }
    double best_area = std::numeric_limits<double>::max();
    // Calipers: indices of the farthest point along v (top), along +u (right), along -u (left).
    size_t top = 0, right = 0, left = 0;
    bool started = false;
    for (size_t i = 0; i < n; ++i) {
        const DVec2 a = hull[i], b = hull[(i + 1) % n];
        const DVec2 d = b - a;
        const double length = glm::length(d);
        if (length == 0.0) continue;
        const DVec2 u = d / length, v(-u.y, u.x);
        auto along = [&](size_t k, const DVec2& axis) { return glm::dot(hull[k % n] - a, axis); };
        if (!started) {
            for (size_t k = 0; k < n; ++k) {
                if (along(k, v) > along(top, v)) top = k;
                if (along(k, u) > along(right, u)) right = k;
                if (along(k, u) < along(left, u)) left = k;
            }
            started = true;
        } else {
            // Each caliper only moves forward around the hull; n steps bound the walk.
            for (size_t s = 0; s < n && along(top + 1, v) >= along(top, v); ++s) top = (top + 1) % n;
            for (size_t s = 0; s < n && along(right + 1, u) >= along(right, u); ++s) right = (right + 1) % n;
            for (size_t s = 0; s < n && along(left + 1, u) <= along(left, u); ++s) left = (left + 1) % n;
        }
        const double u_min = along(left, u), u_max = along(right, u);
        const double v_max = along(top, v);
        const double area = (u_max - u_min) * v_max;
        if (area < best_area) {
            best_area = area;
            best.axis_u = u;
            best.half_extents = DVec2(0.5 * (u_max - u_min), 0.5 * v_max);
            best.center = a + u * (0.5 * (u_min + u_max)) + v * (0.5 * v_max);
        }
    }
    return best;
}

// ---------------------------------------------------------------------------------------
// 3D quickhull over triangles with neighbour links; coplanar triangles are merged at the end.

namespace {

struct QhFace {
    uint32_t v[3];
    int32_t neighbor[3];  // across edge i: v[i] -> v[(i+1)%3]
    DVec3 normal;
    double offset;
    std::vector<uint32_t> outside;
    bool alive = true;
    uint32_t visit = 0;
    double distance(const DVec3& p) const { return glm::dot(normal, p) + offset; }
};

class QuickHull {
public:
    QuickHull(std::span<const DVec3> points, double eps) : p_(points), eps_(eps) {}

    // Returns the simplex dimension found (3 when the hull was built).
    int build(std::vector<uint32_t>& simplex);
    const std::vector<QhFace>& faces() const { return faces_; }

private:
    uint32_t addFace(uint32_t a, uint32_t b, uint32_t c);
    void assign(const std::vector<uint32_t>& candidates, const std::vector<uint32_t>& targets);
    void addPoint(uint32_t face, uint32_t eye);
    int findEdge(const QhFace& f, uint32_t a, uint32_t b) const {
        for (int i = 0; i < 3; ++i)
            if (f.v[i] == a && f.v[(i + 1) % 3] == b) return i;
        return -1;
    }

    std::span<const DVec3> p_;
    double eps_;
    std::vector<QhFace> faces_;
    uint32_t stamp_ = 0;
};

uint32_t QuickHull::addFace(uint32_t a, uint32_t b, uint32_t c) {
    QhFace f;
    f.v[0] = a, f.v[1] = b, f.v[2] = c;
    f.neighbor[0] = f.neighbor[1] = f.neighbor[2] = -1;
    const Plane plane = planeFromPoints(p_[a], p_[b], p_[c]);
    f.normal = plane.normal;
    f.offset = plane.offset;
    faces_.push_back(std::move(f));
    return uint32_t(faces_.size() - 1);
}

void QuickHull::assign(const std::vector<uint32_t>& candidates, const std::vector<uint32_t>& targets) {
    for (uint32_t i : candidates) {
        double best = eps_;
        int32_t best_face = -1;
        for (uint32_t f : targets) {
            const double d = faces_[f].distance(p_[i]);
            if (d > best) {
                best = d;
                best_face = int32_t(f);
                break;  // any face that sees the point will do; the eye choice uses the max
            }
        }
        if (best_face >= 0) faces_[best_face].outside.push_back(i);
    }
}

int QuickHull::build(std::vector<uint32_t>& simplex) {
    const size_t n = p_.size();
    // Initial simplex: the most distant pair among the axis extremes, then the farthest point
    // from their line, then the farthest from their plane.
    uint32_t ext[6] = {0, 0, 0, 0, 0, 0};
    for (uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            if (p_[i][a] < p_[ext[2 * a]][a]) ext[2 * a] = i;
            if (p_[i][a] > p_[ext[2 * a + 1]][a]) ext[2 * a + 1] = i;
        }
    uint32_t i0 = 0, i1 = 0;
    double best = -1.0;
    for (int a = 0; a < 6; ++a)
        for (int b = a + 1; b < 6; ++b) {
            const double d = glm::length2(p_[ext[a]] - p_[ext[b]]);
            if (d > best) best = d, i0 = ext[a], i1 = ext[b];
        }
    simplex = {i0};
    if (std::sqrt(best) <= eps_) return 0;
    simplex.push_back(i1);
    const DVec3 dir = glm::normalize(p_[i1] - p_[i0]);
    uint32_t i2 = i0;
    best = -1.0;
    for (uint32_t i = 0; i < n; ++i) {
        const DVec3 w = p_[i] - p_[i0];
        const double d = glm::length(w - dir * glm::dot(w, dir));
        if (d > best) best = d, i2 = i;
    }
    if (best <= eps_) return 1;
    simplex.push_back(i2);
    const Plane base = planeFromPoints(p_[i0], p_[i1], p_[i2]);
    uint32_t i3 = i0;
    best = -1.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double d = std::abs(base.eval(p_[i]));
        if (d > best) best = d, i3 = i;
    }
    if (best <= eps_) return 2;
    simplex.push_back(i3);

    // Orient the tetrahedron so every face's normal points away from the fourth vertex.
    uint32_t a = i0, b = i1, c = i2;
    if (base.eval(p_[i3]) > 0.0) std::swap(b, c);
    const uint32_t d = i3;
    const uint32_t f0 = addFace(a, b, c), f1 = addFace(a, d, b), f2 = addFace(b, d, c), f3 = addFace(c, d, a);
    // Link neighbours by matching reversed edges.
    const uint32_t all[4] = {f0, f1, f2, f3};
    for (uint32_t f : all)
        for (int e = 0; e < 3; ++e)
            for (uint32_t g : all) {
                if (g == f) continue;
                const int j = findEdge(faces_[g], faces_[f].v[(e + 1) % 3], faces_[f].v[e]);
                if (j >= 0) faces_[f].neighbor[e] = int32_t(g);
            }
    std::vector<uint32_t> rest;
    rest.reserve(n);
    for (uint32_t i = 0; i < n; ++i)
        if (i != a && i != b && i != c && i != d) rest.push_back(i);
    assign(rest, {f0, f1, f2, f3});

    // Process faces with outside points until none remain.
    for (size_t f = 0; f < faces_.size(); ++f) {
        while (faces_[f].alive && !faces_[f].outside.empty()) {
            uint32_t eye = faces_[f].outside[0];
            double far = -1.0;
            for (uint32_t i : faces_[f].outside) {
                const double dist = faces_[f].distance(p_[i]);
                if (dist > far) far = dist, eye = i;
            }
            addPoint(uint32_t(f), eye);
        }
    }
    return 3;
}

void QuickHull::addPoint(uint32_t start, uint32_t eye) {
    const DVec3& p = p_[eye];
    ++stamp_;
    struct HorizonEdge {
        uint32_t a, b;
        int32_t other;  // the hidden face across a->b
    };
    std::vector<uint32_t> visible{start};
    std::vector<HorizonEdge> horizon;
    faces_[start].visit = stamp_;
    // Depth-first over visible faces; walking each face's edges in order after the edge we
    // came in by yields the horizon as one counter-clockwise loop.
    struct Frame {
        uint32_t face;
        int edge, remaining;
    };
    std::vector<Frame> stack{{start, 0, 3}};
    while (!stack.empty()) {
        Frame& frame = stack.back();
        if (frame.remaining == 0) {
            stack.pop_back();
            continue;
        }
        const uint32_t f = frame.face;
        const int e = frame.edge;
        frame.edge = (e + 1) % 3;
        --frame.remaining;
        const int32_t g = faces_[f].neighbor[e];
        if (g < 0) continue;  // cannot happen on a closed hull; be defensive
        if (faces_[g].visit == stamp_) continue;
        const uint32_t va = faces_[f].v[e], vb = faces_[f].v[(e + 1) % 3];
        if (faces_[g].distance(p) > eps_) {
            faces_[g].visit = stamp_;
            visible.push_back(uint32_t(g));
            const int j = findEdge(faces_[g], vb, va);
            stack.push_back({uint32_t(g), (j + 1) % 3, 2});
        } else {
            horizon.push_back({va, vb, g});
        }
    }

    // Collect orphaned points, kill visible faces.
    std::vector<uint32_t> orphans;
    for (uint32_t f : visible) {
        for (uint32_t i : faces_[f].outside)
            if (i != eye) orphans.push_back(i);
        faces_[f].outside.clear();
        faces_[f].outside.shrink_to_fit();
        faces_[f].alive = false;
    }
    // New cone of faces from the horizon to the eye.
    std::vector<uint32_t> created;
    created.reserve(horizon.size());
    for (const HorizonEdge& h : horizon) {
        const uint32_t nf = addFace(h.a, h.b, eye);
        faces_[nf].neighbor[0] = h.other;
        const int j = findEdge(faces_[h.other], h.b, h.a);
        if (j >= 0) faces_[h.other].neighbor[j] = int32_t(nf);
        created.push_back(nf);
    }
    const size_t m = created.size();
    for (size_t k = 0; k < m; ++k) {
        // Edge 1 (b -> eye) meets the next face's edge 2 (eye -> a) since the horizon is a loop.
        const uint32_t cur = created[k], next = created[(k + 1) % m];
        faces_[cur].neighbor[1] = int32_t(next);
        faces_[next].neighbor[2] = int32_t(cur);
    }
    assign(orphans, created);
}

// Boundary loop of a set of hull triangles (a coplanar group); empty if not one loop.
std::vector<uint32_t> groupLoop(const std::vector<QhFace>& faces, const std::vector<uint32_t>& group,
                                const std::vector<int32_t>& group_of, int32_t id) {
    std::unordered_map<uint32_t, uint32_t> next;
    for (uint32_t f : group)
        for (int e = 0; e < 3; ++e) {
            const int32_t g = faces[f].neighbor[e];
            if (g >= 0 && group_of[g] == id) continue;
            if (!next.emplace(faces[f].v[e], faces[f].v[(e + 1) % 3]).second) return {};
        }
    if (next.empty()) return {};
    std::vector<uint32_t> loop;
    const uint32_t first = next.begin()->first;
    uint32_t at = first;
    do {
        loop.push_back(at);
        const auto it = next.find(at);
        if (it == next.end() || loop.size() > next.size()) return {};
        at = it->second;
    } while (at != first);
    return loop.size() == next.size() ? loop : std::vector<uint32_t>{};
}

}  // namespace

Hull3 quickhull(std::span<const DVec3> points, double tolerance) {
    Hull3 hull;
    if (points.empty()) return hull;
    if (tolerance <= 0.0) {
        // Rounding bound of the plane evaluations, in the style of qhull's default.
        DVec3 max_abs(0.0);
        for (const DVec3& p : points) max_abs = glm::max(max_abs, glm::abs(p));
        tolerance = 3.0 * DBL_EPSILON * (max_abs.x + max_abs.y + max_abs.z) * 4.0;
        if (tolerance == 0.0) tolerance = DBL_MIN;
    }
    QuickHull qh(points, tolerance);
    std::vector<uint32_t> simplex;
    const int dimension = qh.build(simplex);
    hull.dimension = dimension;
    if (dimension == 0) {
        hull.vertices = {points[simplex[0]]};
        return hull;
    }
    if (dimension == 1) {
        // The two extremes along the line.
        const DVec3 dir = points[simplex[1]] - points[simplex[0]];
        size_t lo = 0, hi = 0;
        for (size_t i = 0; i < points.size(); ++i) {
            if (glm::dot(points[i], dir) < glm::dot(points[lo], dir)) lo = i;
            if (glm::dot(points[i], dir) > glm::dot(points[hi], dir)) hi = i;
        }
        hull.vertices = {points[lo], points[hi]};
        return hull;
    }
    if (dimension == 2) {
        // Coplanar: the 2D hull in the plane of the first three simplex points, ordered
        // counter-clockwise around that plane's normal.
        const Plane plane = planeFromPoints(points[simplex[0]], points[simplex[1]], points[simplex[2]]);
        DVec3 u, v;
        tangentFrame(plane.normal, u, v);
        std::vector<DVec2> flat(points.size());
        for (size_t i = 0; i < points.size(); ++i) flat[i] = DVec2(glm::dot(points[i], u), glm::dot(points[i], v));
        for (uint32_t i : convexHull2d(flat, tolerance)) hull.vertices.push_back(points[i]);
        hull.planes = {plane};
        return hull;
    }

    // Merge coplanar neighbouring triangles: flood fill from a seed while every vertex of the
    // neighbour lies within tolerance of the seed's plane.
    const std::vector<QhFace>& faces = qh.faces();
    std::vector<int32_t> group_of(faces.size(), -1);
    std::vector<std::vector<uint32_t>> groups;
    // Seeds in order of decreasing area so large faces define the planes.
    std::vector<uint32_t> order;
    for (uint32_t f = 0; f < faces.size(); ++f)
        if (faces[f].alive) order.push_back(f);
    auto area2 = [&](uint32_t f) {
        const QhFace& q = faces[f];
        return glm::length(glm::cross(points[q.v[1]] - points[q.v[0]], points[q.v[2]] - points[q.v[0]]));
    };
    std::vector<double> areas(faces.size(), 0.0);
    for (uint32_t f : order) areas[f] = area2(f);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return areas[a] > areas[b]; });
    for (uint32_t seed : order) {
        if (group_of[seed] >= 0) continue;
        const int32_t id = int32_t(groups.size());
        std::vector<uint32_t> group{seed};
        group_of[seed] = id;
        const QhFace& s = faces[seed];
        for (size_t k = 0; k < group.size(); ++k)
            for (int e = 0; e < 3; ++e) {
                const int32_t g = faces[group[k]].neighbor[e];
                if (g < 0 || group_of[g] >= 0 || !faces[g].alive) continue;
                bool coplanar = glm::dot(faces[g].normal, s.normal) > 0.0;
                for (int c = 0; c < 3 && coplanar; ++c)
                    coplanar = std::abs(s.distance(points[faces[g].v[c]])) <= tolerance;
                if (coplanar) {
                    group_of[g] = id;
                    group.push_back(uint32_t(g));
                }
            }
        groups.push_back(std::move(group));
    }

    std::vector<std::vector<uint32_t>> loops;  // into points
    for (size_t gi = 0; gi < groups.size(); ++gi) {
        std::vector<uint32_t> loop = groupLoop(faces, groups[gi], group_of, int32_t(gi));
        if (loop.size() >= 3) {
            loops.push_back(std::move(loop));
        } else {
            for (uint32_t f : groups[gi]) loops.push_back({faces[f].v[0], faces[f].v[1], faces[f].v[2]});
        }
    }
    // Drop corners that sit on a straight edge of their face: they are no hull vertices. A
    // vertex is kept if it is a corner of any face.
    std::vector<char> corner(points.size(), 0);
    for (const std::vector<uint32_t>& loop : loops) {
        const size_t m = loop.size();
        for (size_t k = 0; k < m; ++k) {
            const DVec3& a = points[loop[(k + m - 1) % m]];
            const DVec3& b = points[loop[k]];
            const DVec3& c = points[loop[(k + 1) % m]];
            const DVec3 ac = c - a;
            const double length = glm::length(ac);
            const double off = length > 0.0 ? glm::length(glm::cross(ac, b - a)) / length : 0.0;
            if (off > tolerance || glm::dot(b - a, ac) <= 0.0 || glm::dot(c - b, ac) <= 0.0) corner[loop[k]] = 1;
        }
    }
    std::vector<int32_t> remap(points.size(), -1);
    for (const std::vector<uint32_t>& loop : loops) {
        std::vector<uint32_t> face;
        for (uint32_t i : loop) {
            if (!corner[i]) continue;
            if (remap[i] < 0) {
                remap[i] = int32_t(hull.vertices.size());
                hull.vertices.push_back(points[i]);
            }
            face.push_back(uint32_t(remap[i]));
        }
        if (face.size() < 3) continue;
        hull.faces.push_back(std::move(face));
    }
    // Planes: Newell normal of each face; offset pushed out to the farthest hull vertex so
    // every hull vertex is on or behind every plane.
    DVec3 centroid(0.0);
    for (const DVec3& p : hull.vertices) centroid += p;
    centroid /= double(hull.vertices.size());
    for (const std::vector<uint32_t>& face : hull.faces) {
        std::vector<DVec3> loop;
        for (uint32_t i : face) loop.push_back(hull.vertices[i]);
        Plane plane = planeFromPolygon(loop);
        double far = -std::numeric_limits<double>::max();
        for (const DVec3& p : hull.vertices) far = std::max(far, glm::dot(plane.normal, p));
        plane.offset = -far;
        hull.planes.push_back(plane);
        // Volume: pyramids from the centroid over each face.
        hull.volume += glm::length(newellNormal(loop)) * 0.5 * std::abs(plane.eval(centroid)) / 3.0;
    }
    return hull;
}

}  // namespace radbake
