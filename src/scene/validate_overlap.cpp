// Coplanar overlapping faces: the same face given twice, or two faces of one plane that
// overlap in part. Either z-fights in any renderer and counts light twice in radiosity.
//
// Near linear: each triangle's plane (unit normal, offset) is quantised into a 4-D cell and
// hashed; only triangles sharing a cell are compared, through a 2-D grid in their plane when
// a cell holds many (a large flat floor). A triangle is also filed under the neighbouring
// cells its tolerance box reaches, so a pair straddling a cell boundary is still found; a pair
// is examined only in the home cell of its smaller triangle, so exactly once.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "scene/validate_overlap.h"

#include "core/memory.h"
#include "scene/coplanar.h"

namespace radbake::validation {
namespace {

// Coplanar: scene/coplanar.h's tolerances, shared with the backs in contact (two_sided.cpp).
constexpr double kCoplanarRelativeTolerance = coplanar::kRelativeTolerance;
constexpr double kNormalTolerance = coplanar::kNormalTolerance;
// Hash cells are this many tolerances wide, so a triangle is filed under ~2 cells on average.
constexpr double kCellsPerTolerance = 16.0;
// A pair is reported when its overlap exceeds this fraction of the smaller polygon's area:
// faces sharing an edge or a corner overlap by nothing (up to rounding), and a sliver of
// interpenetration at tolerance level is not worth a warning.
constexpr double kOverlapFraction = 0.01;
// An overlap covering this fraction of both polygons is the same face given twice.
constexpr double kDuplicateFraction = 0.99;
// Warnings beyond this many mesh pairs are summed up in one note (a file with thousands of
// small boxes overlapping would otherwise bury every other message).
constexpr size_t kMaxOverlapWarnings = 20;
// Groups up to this size are compared pair by pair; larger ones go through a 2-D grid.
constexpr size_t kBruteForceGroup = 24;
// A triangle covering more grid cells than this is compared with the whole group instead.
constexpr int64_t kMaxCellsPerTriangle = 64;
// Bounds on the pairwise work: real scenes examine a few pairs per triangle and keep few
// overlaps; faces stacked by the thousand in one plane make both quadratic.
constexpr size_t kPairsPerTriangle = 16;
constexpr size_t kMinPairBound = size_t{1} << 22;
constexpr size_t kMaxOverlaps = size_t{1} << 20;
// Scratch per triangle (its plane-cell entries, sorted through a second buffer, its home cell
// and size) and per polygon (its area), for the budget check.
constexpr double kBytesPerTriangle = 2 * 2 * sizeof(uint64_t) + sizeof(uint32_t) + sizeof(float);
constexpr double kBytesPerPolygon = sizeof(double);

struct PlaneKey {
    int64_t nx, ny, nz, d;
};

uint64_t mix(uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return h;
}

// 32 bits: a collision only merges two groups, which the exact tests then separate.
inline uint32_t hashKey(const PlaneKey& k) {
    // Odd multipliers make the combination one-to-one for small coordinates; one mix spreads it.
    const uint64_t h = ((static_cast<uint64_t>(k.nx) * 0x9E3779B97F4A7C15ull + static_cast<uint64_t>(k.ny)) *
                            0xC2B2AE3D27D4EB4Full +
                        static_cast<uint64_t>(k.nz)) *
                           0x165667B19E3779F9ull +
                       static_cast<uint64_t>(k.d);
    return static_cast<uint32_t>(mix(h) >> 32);
}

// Counting-sort pass on 11 bits of the hash, stable; `count` holds 2049 zeros on entry.
void radixPass(const uint64_t* in, uint64_t* out, size_t n, int shift, size_t* count) {
    for (size_t i = 0; i < n; ++i) ++count[((in[i] >> shift) & 2047) + 1];
    for (size_t i = 1; i <= 2048; ++i) count[i] += count[i - 1];
    for (size_t i = 0; i < n; ++i) out[count[(in[i] >> shift) & 2047]++] = in[i];
}

// Sorts (hash << 32 | triangle) by hash only, stably (so triangles stay ascending in a group).
// Beyond the cache, one pass on the top 11 bits of the hash splits the entries into 2048 runs
// that fit in it, then two passes sort each run on the lower 21 bits.
void radixSortByHigh32(std::vector<uint64_t>& values) {
    std::vector<uint64_t> scratch(values.size());
    std::array<size_t, 2049> count{};
    if (values.size() < (size_t(1) << 20)) {  // in cache anyway: three plain passes, low to high
        for (int shift = 32; shift < 64; shift += 11) {
            count.fill(0);
            radixPass(values.data(), scratch.data(), values.size(), shift, count.data());
            values.swap(scratch);
        }
        return;
    }
    radixPass(values.data(), scratch.data(), values.size(), 53, count.data());
    // count[b] is now the end of bucket b (and the start of bucket b + 1).
    size_t begin = 0;
    for (size_t bucket = 0; bucket < 2048; ++bucket) {
        const size_t end = count[bucket];
        std::array<size_t, 2049> inner{};
        radixPass(scratch.data() + begin, values.data() + begin, end - begin, 32, inner.data());
        inner.fill(0);
        radixPass(values.data() + begin, scratch.data() + begin, end - begin, 43, inner.data());
        begin = end;
    }
    values.swap(scratch);
}

struct Layout {
    std::vector<size_t> first_triangle;  // per mesh, plus the total
    std::vector<size_t> first_polygon;   // per mesh, plus the total
};

Layout layoutOf(const std::vector<Mesh>& meshes) {
    Layout layout;
    layout.first_triangle.push_back(0);
    layout.first_polygon.push_back(0);
    for (const Mesh& mesh : meshes) {
        layout.first_triangle.push_back(layout.first_triangle.back() + mesh.triangles.size());
        layout.first_polygon.push_back(layout.first_polygon.back() + mesh.polygon_count);
    }
    return layout;
}

size_t ownerOf(const std::vector<size_t>& firsts, size_t global) {
    return static_cast<size_t>(std::upper_bound(firsts.begin(), firsts.end(), global) - firsts.begin()) - 1;
}

// Longest edge, rounded to float so that every use compares the same value.
float longestEdge(const Mesh& mesh, size_t t) {
    const UVec3& tri = mesh.triangles[t];
    const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
    return static_cast<float>(std::sqrt(std::max({glm::length2(b - a), glm::length2(c - b), glm::length2(a - c)})));
}

// One triangle, ready for the exact tests.
struct Member {
    uint32_t triangle = 0;  // global
    uint32_t polygon = 0;   // global
    std::array<DVec3, 3> p;
    DVec3 normal{0.0};      // unit
    double area = 0.0;
    DVec2 lo{0.0}, hi{0.0};  // bounding box in the group's projection
};

Member makeMember(const std::vector<Mesh>& meshes, const Layout& layout, uint32_t triangle) {
    const size_t m = ownerOf(layout.first_triangle, triangle);
    const Mesh& mesh = meshes[m];
    const size_t t = triangle - layout.first_triangle[m];
    const UVec3& tri = mesh.triangles[t];
    Member member;
    member.triangle = triangle;
    member.polygon = static_cast<uint32_t>(layout.first_polygon[m] + mesh.triangle_polygon[t]);
    member.p = {DVec3(mesh.positions[tri.x]), DVec3(mesh.positions[tri.y]), DVec3(mesh.positions[tri.z])};
    const DVec3 n = glm::cross(member.p[1] - member.p[0], member.p[2] - member.p[0]);
    const double twice = glm::length(n);
    member.normal = n / twice;
    member.area = 0.5 * twice;
    return member;
}

// floor() without a libm call (this runs several times per triangle); |x| < 2^62.
int64_t floorToInt(double x) {
    const int64_t truncated = static_cast<int64_t>(x);
    return truncated - (x < static_cast<double>(truncated));
}

using coplanar::clipTriangle;
using coplanar::cross2;
using coplanar::dominantAxis;
using coplanar::Polygon2;
using coplanar::project;

struct Overlap {
    double area = 0.0;  // 3-D area of the intersection
    DVec3 point{0.0};   // a point inside it (of its largest piece)
    double piece = 0.0;
};

class OverlapFinder {
public:
    OverlapFinder(const std::vector<Mesh>& meshes, double extent)
        : meshes_(meshes), layout_(layoutOf(meshes)) {
        tolerance_ = std::max(kCoplanarRelativeTolerance * extent, std::numeric_limits<double>::min());
        max_pairs_ = std::max(kMinPairBound, kPairsPerTriangle * layout_.first_triangle.back());
    }

    void run() {
        std::vector<uint64_t> entries = fileTriangles();
        radixSortByHigh32(entries);
        std::vector<uint32_t> group;
        for (size_t begin = 0; begin < entries.size() && !stopped_;) {
            const uint32_t hash = static_cast<uint32_t>(entries[begin] >> 32);
            size_t end = begin + 1;
            while (end < entries.size() && static_cast<uint32_t>(entries[end] >> 32) == hash) ++end;
            if (end - begin >= 2) {
                group.clear();
                for (size_t i = begin; i < end; ++i) {
                    const uint32_t t = static_cast<uint32_t>(entries[i]);
                    if (group.empty() || group.back() != t) group.push_back(t);  // two cells may collide
                }
                if (group.size() >= 2) examineGroup(group, hash);
            }
            begin = end;
        }
    }

    const std::unordered_map<uint64_t, Overlap>& overlaps() const { return overlaps_; }
    const std::vector<double>& polygonAreas() const { return polygon_area_; }
    const Layout& layout() const { return layout_; }
    bool stopped() const { return stopped_; }
    size_t pairsExamined() const { return pairs_; }

private:
    // Files every triangle under the hash of each plane cell its tolerance box reaches, and
    // records its home cell, its size and its polygon's area.
    //
    // A plane cell is a normal cell K (cells of the unit normal's components) and a cell of the
    // offset measured along K's centre normal n_K, from the scene's centre o. Measuring along
    // n_K, not the triangle's own normal, keeps the offset tolerance local: for a pair s, l that
    // passes the exact tests (examinePair), with s no larger than l and K = s's normal cell,
    //   |n_K.(c_s - o) - n_K.(c_l - o)| <= |n_s.(c_s - c_l)| + |n_K - n_s| |c_s - c_l|
    //                                   <= tolerance + (sqrt(3) / 2) cell_n * 2 size_l,
    // (c the centroids, size the longest edge; overlapping triangles' centroids are at most
    // size_s + size_l apart), so filing l under that box around its own offset, and examining
    // a pair only in the home cell of its smaller triangle, finds every pair exactly once.
    std::vector<uint64_t> fileTriangles() {
        DVec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (const Mesh& mesh : meshes_)
            for (const Vec3& p : mesh.positions) {
                lo = glm::min(lo, DVec3(p));
                hi = glm::max(hi, DVec3(p));
            }
        const DVec3 origin = 0.5 * (lo + hi);

        const size_t triangle_count = layout_.first_triangle.back();
        home_.resize(triangle_count);
        size_.resize(triangle_count);
        polygon_area_.assign(layout_.first_polygon.back(), 0.0);
        // Offset cells are sized for the median triangle (sampled): larger ones span a few cells.
        std::vector<float> sample;
        const size_t step = std::max<size_t>(1, triangle_count / 50000);
        for (size_t t = 0; t < triangle_count; t += step) {
            const size_t m = ownerOf(layout_.first_triangle, t);
            sample.push_back(longestEdge(meshes_[m], t - layout_.first_triangle[m]));
        }
        double median_size = 0.0;
        if (!sample.empty()) {
            std::nth_element(sample.begin(), sample.begin() + sample.size() / 2, sample.end());
            median_size = sample[sample.size() / 2];
        }
        const double normal_cell = kCellsPerTolerance * kNormalTolerance;
        const double slope = std::sqrt(3.0) * normal_cell;  // offset tolerance per unit of triangle size
        const double offset_cell =
            std::max(kCellsPerTolerance * (tolerance_ + slope * median_size), std::numeric_limits<double>::min());
        // Boxes are 5 % wider than the bounds: slack for rounding in these sums (about 1e-15 relative).
        const double normal_box = 1.05 * kNormalTolerance;
        const double per_normal_cell = 1.0 / normal_cell, per_offset_cell = 1.0 / offset_cell;
        auto cellOf = [](double value, double inverse_cell) { return floorToInt(value * inverse_cell + 0.5); };

        std::vector<uint64_t> entries;
        entries.reserve(2 * triangle_count + 16);
        uint32_t global = 0;
        for (size_t m = 0; m < meshes_.size(); ++m) {
            const Mesh& mesh = meshes_[m];
            for (size_t t = 0; t < mesh.triangles.size(); ++t, ++global) {
                const UVec3& tri = mesh.triangles[t];
                const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
                const DVec3 n = glm::cross(b - a, c - a);
                const double twice_area = glm::length(n);
                polygon_area_[layout_.first_polygon[m] + mesh.triangle_polygon[t]] += 0.5 * twice_area;
                size_[global] = longestEdge(mesh, t);
                const DVec3 unit = n / twice_area;
                const DVec3 centre = (a + b + c) / 3.0 - origin;
                const double offset_box = 1.05 * (tolerance_ + slope * size_[global]);
                // Cells are centred on multiples of the cell size, so axis-aligned planes (the
                // commonest by far) sit mid-cell and are filed once.
                std::array<int64_t, 3> first{}, last{}, own{};
                for (int k = 0; k < 3; ++k) {
                    first[k] = cellOf(unit[k] - normal_box, per_normal_cell);
                    last[k] = cellOf(unit[k] + normal_box, per_normal_cell);
                    own[k] = cellOf(unit[k], per_normal_cell);
                }
                {
                    const DVec3 n_cell = DVec3(own[0], own[1], own[2]) * normal_cell;
                    home_[global] = hashKey({own[0], own[1], own[2], cellOf(glm::dot(n_cell, centre), per_offset_cell)});
                }
                for (int64_t i = first[0]; i <= last[0]; ++i)
                    for (int64_t j = first[1]; j <= last[1]; ++j)
                        for (int64_t k = first[2]; k <= last[2]; ++k) {
                            const double offset = glm::dot(DVec3(i, j, k) * normal_cell, centre);
                            const int64_t d_last = cellOf(offset + offset_box, per_offset_cell);
                            for (int64_t d = cellOf(offset - offset_box, per_offset_cell); d <= d_last; ++d)
                                entries.push_back(uint64_t(hashKey({i, j, k, d})) << 32 | global);
                        }
            }
        }
        return entries;
    }

    // The pair's smaller triangle (by size, then number) owns it: see fileTriangles.
    uint32_t owner(uint32_t s, uint32_t t) const {
        return size_[s] < size_[t] || (size_[s] == size_[t] && s < t) ? s : t;
    }

    void examineGroup(const std::vector<uint32_t>& group, uint32_t hash) {
        // Pairs are examined in their lower triangle's home cell: without a home member, none is.
        if (std::none_of(group.begin(), group.end(), [&](uint32_t t) { return home_[t] == hash; })) return;
        members_.clear();
        for (uint32_t t : group) members_.push_back(makeMember(meshes_, layout_, t));
        const int axis = dominantAxis(members_[0].normal);
        for (Member& m : members_) {
            const DVec2 a = project(m.p[0], axis), b = project(m.p[1], axis), c = project(m.p[2], axis);
            m.lo = glm::min(a, glm::min(b, c));
            m.hi = glm::max(a, glm::max(b, c));
        }
        if (members_.size() <= kBruteForceGroup) {
            for (size_t i = 0; i < members_.size() && !stopped_; ++i)
                for (size_t j = i + 1; j < members_.size(); ++j)
                    if (boxesOverlap(members_[i], members_[j])) examinePair(members_[i], members_[j], hash);
            return;
        }
        examineThroughGrid(hash);
    }

    static bool boxesOverlap(const Member& a, const Member& b) {
        return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y;
    }

    // A uniform grid over the group's projection, cells about the median triangle's size;
    // a pair sharing several cells is examined only in the cell holding its boxes' common corner.
    void examineThroughGrid(uint32_t hash) {
        const size_t n = members_.size();
        DVec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        sizes_.clear();
        for (const Member& m : members_) {
            lo = glm::min(lo, m.lo);
            hi = glm::max(hi, m.hi);
            sizes_.push_back(std::max(m.hi.x - m.lo.x, m.hi.y - m.lo.y));
        }
        std::nth_element(sizes_.begin(), sizes_.begin() + n / 2, sizes_.end());
        const DVec2 span = hi - lo;
        double cell = std::max({sizes_[n / 2], span.x * 1e-6, span.y * 1e-6, std::numeric_limits<double>::min()});
        auto cellsAlong = [&](double length) { return static_cast<int64_t>(std::floor(length / cell)) + 1; };
        while (double(cellsAlong(span.x)) * double(cellsAlong(span.y)) > 4.0 * double(n)) cell *= 2.0;
        const int64_t nx = cellsAlong(span.x), ny = cellsAlong(span.y);
        const double per_cell = 1.0 / cell;
        auto cellX = [&](double x) { return std::clamp<int64_t>(floorToInt((x - lo.x) * per_cell), 0, nx - 1); };
        auto cellY = [&](double y) { return std::clamp<int64_t>(floorToInt((y - lo.y) * per_cell), 0, ny - 1); };

        // Counting sort of (cell, member).
        cell_start_.assign(static_cast<size_t>(nx * ny + 1), 0);
        big_.clear();
        for (uint32_t i = 0; i < n; ++i) {
            const Member& m = members_[i];
            const int64_t x0 = cellX(m.lo.x), x1 = cellX(m.hi.x), y0 = cellY(m.lo.y), y1 = cellY(m.hi.y);
            if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMaxCellsPerTriangle) {
                big_.push_back(i);
                continue;
            }
            for (int64_t y = y0; y <= y1; ++y)
                for (int64_t x = x0; x <= x1; ++x) ++cell_start_[static_cast<size_t>(y * nx + x) + 1];
        }
        for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
        cell_members_.resize(cell_start_.back());
        std::vector<size_t> fill(cell_start_.begin(), cell_start_.end() - 1);
        std::vector<bool> is_big(n, false);
        for (uint32_t i : big_) is_big[i] = true;
        for (uint32_t i = 0; i < n; ++i) {
            if (is_big[i]) continue;
            const Member& m = members_[i];
            const int64_t x0 = cellX(m.lo.x), x1 = cellX(m.hi.x), y0 = cellY(m.lo.y), y1 = cellY(m.hi.y);
            for (int64_t y = y0; y <= y1; ++y)
                for (int64_t x = x0; x <= x1; ++x) cell_members_[fill[static_cast<size_t>(y * nx + x)]++] = i;
        }
        for (int64_t y = 0; y < ny; ++y)
            for (int64_t x = 0; x < nx; ++x) {
                const size_t c = static_cast<size_t>(y * nx + x);
                for (size_t i = cell_start_[c]; i < cell_start_[c + 1] && !stopped_; ++i)
                    for (size_t j = i + 1; j < cell_start_[c + 1]; ++j) {
                        const Member& a = members_[cell_members_[i]];
                        const Member& b = members_[cell_members_[j]];
                        if (!boxesOverlap(a, b)) continue;
                        if (cellX(std::max(a.lo.x, b.lo.x)) != x || cellY(std::max(a.lo.y, b.lo.y)) != y) continue;
                        examinePair(a, b, hash);
                    }
            }
        for (uint32_t b : big_)
            for (uint32_t i = 0; i < n && !stopped_; ++i)
                if (i != b && !(is_big[i] && i < b) && boxesOverlap(members_[i], members_[b]))
                    examinePair(members_[i], members_[b], hash);
    }

    // The exact tests: same side, normals and planes within tolerance, then the area of the
    // triangles' intersection in their common plane.
    void examinePair(const Member& a, const Member& b, uint32_t hash) {
        if (home_[owner(a.triangle, b.triangle)] != hash) return;  // examined in another cell
        if (stopped_) return;
        if (++pairs_ > max_pairs_ || overlaps_.size() >= kMaxOverlaps) {
            stopped_ = true;
            return;
        }
        if (a.polygon == b.polygon) return;
        if (glm::dot(a.normal, b.normal) <= 0.0) return;  // back to back: a thin wall
        const DVec3 dn = glm::abs(a.normal - b.normal);
        if (dn.x > kNormalTolerance || dn.y > kNormalTolerance || dn.z > kNormalTolerance) return;
        for (int k = 0; k < 3; ++k)
            if (std::abs(glm::dot(a.normal, b.p[k] - a.p[0])) > tolerance_ ||
                std::abs(glm::dot(b.normal, a.p[k] - b.p[0])) > tolerance_)
                return;

        // In a's plane, dropping its dominant axis, relative to a's first corner.
        const int axis = dominantAxis(a.normal);
        std::array<DVec2, 3> ta, tb;
        for (int k = 0; k < 3; ++k) {
            ta[k] = project(a.p[k] - a.p[0], axis);
            tb[k] = project(b.p[k] - a.p[0], axis);
        }
        if (cross2(ta[1] - ta[0], ta[2] - ta[0]) < 0.0) std::swap(ta[1], ta[2]);
        if (cross2(tb[1] - tb[0], tb[2] - tb[0]) < 0.0) std::swap(tb[1], tb[2]);
        // Separating edges first: neighbours sharing an edge or a corner (exactly the same
        // vertices give exactly zero here) are settled without clipping.
        auto separates = [](const std::array<DVec2, 3>& from, const std::array<DVec2, 3>& other) {
            for (int k = 0; k < 3; ++k) {
                const DVec2 edge = from[(k + 1) % 3] - from[k];
                if (cross2(edge, other[0] - from[k]) <= 0.0 && cross2(edge, other[1] - from[k]) <= 0.0 &&
                    cross2(edge, other[2] - from[k]) <= 0.0)
                    return true;
            }
            return false;
        };
        if (separates(ta, tb) || separates(tb, ta)) return;
        Polygon2 buffers[2];  // ping-pong, not copied: this runs for every pair of neighbours
        Polygon2* poly = nullptr;
        const int count = clipTriangle(ta, tb, buffers, poly);
        if (count < 3) return;
        double twice = 0.0;
        DVec2 moment(0.0);
        for (int k = 0; k < count; ++k) {
            const DVec2& p = (*poly)[k];
            const DVec2& q = (*poly)[(k + 1) % count];
            const double c = cross2(p, q);
            twice += c;
            moment += c * (p + q);
        }
        const double area = 0.5 * std::abs(twice) / std::abs(a.normal[axis]);  // back to 3-D area
        // Neighbours sharing an edge clip to a sliver of rounding size: not an overlap.
        if (!(area > 1e-6 * std::min(a.area, b.area))) return;
        const DVec2 centre = moment / (3.0 * twice);  // the intersection's centroid
        const std::array<int, 2> uv = axis == 0 ? std::array<int, 2>{1, 2}
                                                : (axis == 1 ? std::array<int, 2>{2, 0} : std::array<int, 2>{0, 1});
        DVec3 point(0.0);
        point[uv[0]] = centre.x;
        point[uv[1]] = centre.y;
        point[axis] = -(a.normal[uv[0]] * centre.x + a.normal[uv[1]] * centre.y) / a.normal[axis];
        const uint64_t key = uint64_t(std::min(a.polygon, b.polygon)) << 32 | std::max(a.polygon, b.polygon);
        Overlap& overlap = overlaps_[key];
        overlap.area += area;
        if (area > overlap.piece) {
            overlap.piece = area;
            overlap.point = a.p[0] + point;
        }
    }

    const std::vector<Mesh>& meshes_;
    Layout layout_;
    double tolerance_ = 0.0;
    std::vector<uint32_t> home_;  // per triangle: hash of its own plane cell
    std::vector<float> size_;     // per triangle: longest edge
    std::vector<double> polygon_area_;
    std::unordered_map<uint64_t, Overlap> overlaps_;  // (polygon, polygon) -> overlap
    size_t pairs_ = 0, max_pairs_ = 0;
    bool stopped_ = false;  // a bound was reached: what was found so far is reported
    // Scratch reused across groups.
    std::vector<Member> members_;
    std::vector<double> sizes_;
    std::vector<size_t> cell_start_;
    std::vector<uint32_t> cell_members_;
    std::vector<uint32_t> big_;
};

std::string pointText(const DVec3& p) {
    auto number = [](double v) {
        char text[32];
        std::snprintf(text, sizeof text, "%.6g", std::abs(v) < 1e-12 ? 0.0 : v);
        return std::string(text);
    };
    return "(" + number(p.x) + ", " + number(p.y) + ", " + number(p.z) + ")";
}

struct MeshPairReport {
    size_t duplicates = 0;
    size_t partial = 0;
    uint64_t example = UINT64_MAX;  // smallest polygon pair, for a stable message
    DVec3 point{0.0};
};

}  // namespace

bool overlapCheckFits(const Scene& scene, double max_memory_mb, Diagnostics& diagnostics) {
    double triangles = 0.0, polygons = 0.0;
    for (const Mesh& mesh : scene.meshes) {
        triangles += static_cast<double>(mesh.triangles.size());
        polygons += static_cast<double>(mesh.polygon_count);
    }
    const double bytes = triangles * kBytesPerTriangle + polygons * kBytesPerPolygon;
    if (fitsMemoryBudget(max_memory_mb, bytes)) return true;
    char message[256];
    std::snprintf(message, sizeof message,
                  "validating the scene's %.0f triangles needs about %s more, above the memory budget of %s "
                  "(--max-memory)",
                  triangles, bytesText(bytes).c_str(), bytesText(max_memory_mb * 1048576.0).c_str());
    diagnostics.error({scene.source_path, 0, 0}, message);
    return false;
}

void reportCoplanarOverlaps(const std::vector<Mesh>& meshes, Diagnostics& diagnostics) {
    OverlapFinder finder(meshes, sceneExtent(meshes));
    finder.run();
    if (finder.stopped() && !meshes.empty())
        diagnostics.note(meshes.front().location,
                         "the coplanar overlap check stopped after " + std::to_string(finder.pairsExamined()) +
                             " face pairs (faces stacked on each other in one plane); overlaps after that are "
                             "not reported");
    const Layout& layout = finder.layout();
    const std::vector<double>& areas = finder.polygonAreas();
    std::map<std::pair<size_t, size_t>, MeshPairReport> reports;
    for (const auto& [key, overlap] : finder.overlaps()) {
        const size_t p = key >> 32, q = key & 0xffffffffu;
        if (overlap.area < kOverlapFraction * std::min(areas[p], areas[q])) continue;
        MeshPairReport& report = reports[{ownerOf(layout.first_polygon, p), ownerOf(layout.first_polygon, q)}];
        if (overlap.area >= kDuplicateFraction * std::max(areas[p], areas[q]))
            ++report.duplicates;
        else
            ++report.partial;
        if (key < report.example) {
            report.example = key;
            report.point = overlap.point;
        }
    }
    size_t reported = 0, unreported_pairs = 0, unreported_face_pairs = 0;
    SourceLocation first_unreported;
    for (const auto& [mesh_pair, report] : reports) {
        const auto [ma, mb] = mesh_pair;
        if (reported == kMaxOverlapWarnings) {
            if (unreported_pairs++ == 0) first_unreported = meshes[mb].location;
            unreported_face_pairs += report.duplicates + report.partial;
            continue;
        }
        ++reported;
        const Mesh& a = meshes[ma];
        const Mesh& b = meshes[mb];
        std::string counts;
        if (report.duplicates > 0)
            counts = std::to_string(report.duplicates) + " duplicate coplanar face(s) covering the same area";
        if (report.partial > 0)
            counts += (counts.empty() ? "" : ", ") + std::to_string(report.partial) +
                      " coplanar face pair(s) partly overlapping, facing the same way";
        const size_t pa = (report.example >> 32) - layout.first_polygon[ma];
        const size_t pb = (report.example & 0xffffffffu) - layout.first_polygon[mb];
        const std::string example = " (e.g. polygon " + std::to_string(pa) + " and polygon " + std::to_string(pb) +
                                    ", at " + pointText(report.point) + ")";
        const std::string who = ma == mb ? describeMesh(a, ma) : describeMesh(a, ma) + " and " + describeMesh(b, mb);
        diagnostics.warning(b.location, who + ": " + counts + example);
    }
    if (unreported_pairs > 0)
        diagnostics.note(first_unreported, std::to_string(unreported_pairs) + " more mesh pair(s) with " +
                                               std::to_string(unreported_face_pairs) +
                                               " overlapping coplanar face pair(s) not reported");
}

}  // namespace radbake::validation
