#pragma once
// Irradiance on the scene's surfaces from the solution's links (issue 12): the "local pass"
// of Smits et al. 1994 and Christensen et al. 1996. A point of a leaf element gathers only
// from the sources of the links that reach that leaf or one of its ancestors (together they
// cover, once, everything the solver let light the point), with exact point-to-polygon
// form factors, each source opened like the exhaustive gather opens elements, and:
//   - a link's own visibility where the solver knows it (1 proven by its shaft: no rays;
//     0 proven: nothing); for the others (partly visible, or found wholly visible or wholly
//     hidden by the solver's few rays, between which a shadow edge may pass) rays at the point where the source
//     may bring more than a small share of the point's light, the link's own visibility
//     elsewhere;
//   - cluster links likewise: a pairwise link's member pairs gathered like element links
//     (rays unless its shaft proved it visible; a pair whose one ray was blocked as a link
//     whose rays were all blocked), a separable link (far, wholly visible) member by member
//     without rays when its source is small, else by the solve's own product form, its
//     receiver cosine taken at the point;
//   - punctual lights' direct light by rays, as probeIrradiance.
// probeIrradiance (the exhaustive gather from every root, rays for every element) stays the
// reference: --texel-tolerance 0 and --quality reference use it.
#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/parallel.h"
#include "readout/evaluate_probe.h"
#include "radiosity/solution.h"

namespace radbake {

namespace gather {
struct Gatherer;
}

class LinkReconstruction {
public:
    // Tables over the solution (link ranges, which roots a source polygon became, the
    // cluster light per root): the solution must outlive it and stay unchanged.
    LinkReconstruction(const Solution& solution, const ReadoutOptions& options, ParallelRunner& runner);

    // What a point is, for the edge correction: EdgeCorrection::Shared corrects lightmap texels
    // (an output, few of them on an edge) but not probes.
    enum class Reading { Probe, Texel };
    // H (W/m^2) at p_world, a point of triangle `triangle` of Scene::meshes[mesh], on the side
    // `normal` faces (unit; the triangle's normal). Where the triangle has no element
    // (degenerate) or faces the other way: probeIrradiance. Thread-safe, deterministic.
    DVec3 irradiance(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal,
                     Reading reading = Reading::Probe) const;
    DVec3 irradianceCounted(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal,
                            ProbeCounters& counters, Reading reading = Reading::Probe) const;

    // The leaf element holding p_world on that triangle (kNoElement: none); ties go to the
    // first element in order.
    uint32_t leafAt(uint32_t mesh, uint32_t triangle, const DVec3& p_world) const;

    // The same split in two, for a caller that reads several faces at one point (the vertex
    // bake, at a vertex on an edge): H without the edge correction, then the correction's terms
    // (edgeTermsAt), solved with the other faces' by correctTogether. A face beside the point
    // whose normal is one of `beside`'s takes that H instead of being read once more through
    // its own links; with EdgeCorrection::Shared only those faces are corrected for, with Off
    // none. irradiance() does the same with the faces beside it reads itself, at On (texels:
    // and Shared).
    // Normals closer than this (1 - cos) are one plane: a SideLight stands for the face beside
    // of its normal, and the vertex bake groups a point's faces by it.
    static constexpr double kSameNormal = 1e-6;
    struct SideLight {
        DVec3 normal;  // unit
        DVec3 h;       // H there: uncorrected, or as correctTogether has corrected it so far
    };
    DVec3 irradianceUncorrected(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal) const;
    // surfaceIrradiance (the exhaustive gather at a point of that triangle), counted in work().
    DVec3 irradianceExhaustive(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal) const;
    // The correction is linear in what each face beside gets at the point: per face,
    // sum over its touching leaves of w (B_mean - E - rho H_beside). Kept in that form, a
    // caller that knows every face's H at the point (the vertex bake) can solve their mutual
    // dependence: at a room's corner each face's H at the corner reads the two others, and
    // one correction from their uncorrected H left the tessellated Cornell box's corners +6 %.
    struct EdgeTerms {
        struct Face {
            DVec3 normal;          // of the face beside (its leaf at the point)
            double weight = 0.0;   // sum of w over its touching leaves
            DVec3 weighted_mean;   // sum of w B_mean
            DVec3 emission, reflectance;  // of its leaf at the point
            DVec3 h_read;          // its H at the point read through its own links (not in `beside`)
            uint32_t leaf = 0;     // its leaf at the point
        };
        std::vector<Face> faces;
        // The correction with the faces beside at the H `beside` gives (by normal), else h_read.
        DVec3 correction(std::span<const SideLight> beside) const;
    };
    // The faces that meet at a point corrected together: sides[g].h from uncorrected[g] plus
    // terms[g]'s correction with the others at their corrected H, by Jacobi steps (each step
    // contracts by at most the faces' near form factor times their reflectance, 0.75 x 0.75 at
    // a room's corner; one step from the uncorrected H left the tessellated Cornell box's
    // corners +6.4 %).
    static void correctTogether(std::span<SideLight> sides, std::span<const DVec3> uncorrected,
                                std::span<const EdgeTerms> terms);
    // `interior`: the direction into the point's own face along which its value is the limit
    // (unit, in its plane; zero: not known), where a face beside without a SideLight is read:
    // at a block's convex corner the floor's light there depends on the way in.
    EdgeTerms edgeTermsAt(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal,
                          const DVec3& h, std::span<const SideLight> beside, const DVec3& interior = DVec3(0.0)) const;

    // The work done so far by every read (irradiance, its variants and edgeTermsAt): points read,
    // and their rays, form factors and pieces. Deterministic: each point's work is its own.
    using Work = ReadoutWork;
    Work work() const;

private:
    void tally(const ProbeCounters& c, size_t points) const;
    // The leaf holding the point when the point reads its links (on its front side), else
    // kNoElement (read by probeIrradiance).
    uint32_t readingLeaf(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal) const;
    DVec3 evaluate(uint32_t mesh, uint32_t triangle, const DVec3& p_world, const DVec3& normal,
                   ProbeCounters* counters, bool edges) const;
    // The light through the links of `leaf` (no punctual lights); `edges`: with the
    // correction where the point touches a face at a concave edge (reconstruct.cpp).
    DVec3 evaluateLeaf(uint32_t leaf, const DVec3& p_world, const DVec3& normal, ProbeCounters* counters,
                       bool edges) const;
    // The roots that can touch the point (its own, its links' sources', its cluster pairs'
    // members within lift of it), at most 64, and the lift direction off them (gather.h).
    struct Touched {
        std::array<uint32_t, 64> roots{};
        size_t count = 0;
        DVec3 direction{0.0};
    };
    Touched touchedRoots(uint32_t leaf, const DVec3& p_world) const;
    // `lifted`: the point as the gather reads it (off the planes it touches); `beside_only`:
    // only the faces `beside` gives.
    EdgeTerms edgeTerms(uint32_t leaf, const DVec3& p_world, const DVec3& lifted, const DVec3& normal, const DVec3& h,
                        std::span<const uint32_t> touched, std::span<const SideLight> beside, bool beside_only,
                        const DVec3& interior, ProbeCounters* counters) const;
    // H of the face beside (normal `beside_normal`, its roots touching the point
    // `plane_roots`) seen from a point at the end of the edge the two share: the mean over
    // sectors around the point, each weighted by its form factor from the way in
    // (reconstruct.cpp, kCornerSectors).
    DVec3 sectorRead(const DVec3& p_world, const DVec3& normal, const DVec3& beside_normal, const DVec3& interior,
                     std::span<const uint32_t> plane_roots, ProbeCounters* counters) const;
    // The leaf below element e that holds p_world (nearest child at each level).
    uint32_t leafBelow(uint32_t e, const DVec3& p_world) const;
    struct PendingSource {
        uint32_t source;  // element
        double form_factor;  // from the point, unoccluded (< 0: a far-field estimate weights it)
        double light;     // f B (max channel), unoccluded
        DVec3 fallback;   // its light without rays
        bool partial;     // its link's rays disagreed (0 < visibility < 1)
    };
    // f(source member, kernel, link) for every member pair of a pairwise cluster link that
    // reaches `root`, in a fixed order; kernel 0: the pair faces away or its ray was blocked.
    template <class F>
    void forClusterPairs(uint32_t root, F&& f) const;
    // forClusterPairs(root) once per root and thread, kept for every point read on that root
    // (a chart's texels and a mesh's vertices come root by root): enumerating the pairs was a
    // quarter of a texel's time in a lit room. In forClusterPairs' order, without what can
    // matter at no point of the root.
    struct RootPair {
        uint32_t member;
        uint32_t link;  // in Solution::cluster_links
        double kernel;
    };
    struct RootPairs {
        uint64_t owner = 0;          // id_ of the LinkReconstruction they were built for
        uint32_t root = 0xffffffffu;
        std::vector<RootPair> lit;   // kernel > 0, or the member can face a point of the root
        std::vector<uint32_t> near;  // members (each time they occur) that can come within lift of it
    };
    const RootPairs& pairsOf(uint32_t root) const;
    void gatherLinks(uint32_t leaf, gather::Gatherer& g, std::vector<PendingSource>& pending,
                     DVec3& separable) const;
    void listDeferred(std::span<const std::pair<uint32_t, double>> deferred, gather::Gatherer& g,
                      std::vector<PendingSource>& pending) const;

    const Solution& s_;
    ReadoutOptions o_;
    uint64_t id_;  // unique per object, so a thread's RootPairs never outlive theirs unnoticed
    std::vector<size_t> link_begin_;  // per element + 1: its links in Solution::links
    struct RootKey {
        uint32_t mesh, polygon, root;
    };
    std::vector<RootKey> roots_;      // sorted by (mesh, polygon, root)
    // Clustering (empty without cluster links).
    std::vector<size_t> cluster_begin_;     // per receiver key (roots, then clusters) + 1
    std::vector<DVec3> separable_flux_;     // per separable cluster link: sum_i s_i B_i (cluster.cpp)
    mutable std::atomic<size_t> points_{0}, rays_{0}, form_factors_{0}, pieces_{0};
};

}  // namespace radbake
