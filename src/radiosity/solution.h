#pragma once
// The solved hierarchy: elements (quadtrees over the scene's convex source polygons), the
// links that carry light between them, and each element's radiosity. Built by
// solveRadiosity, read by the bake stage (bakeVertices, lightmaps) and by probes.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "geometry/types.h"
#include "radiosity/solver_options.h"
#include "scene/scene.h"

namespace radbake {

class RayCaster;
struct PartSet;

inline constexpr uint32_t kNoElement = 0xffffffffu;

// A flat convex polygon of the hierarchy. Roots are source polygons (or, for a non-convex
// or non-planar polygon, its triangles); a split gives one quad per vertex (vertex, edge
// midpoint, centre, edge midpoint), so every element below the roots is a quad.
struct Element {
    uint32_t first_vertex = 0;   // into Solution::vertices
    uint32_t vertex_count = 0;   // 3..n for roots, 4 below
    uint32_t parent = kNoElement;
    uint32_t first_child = kNoElement;  // children are contiguous
    uint32_t child_count = 0;
    uint32_t root = 0;           // index of its root element
    uint32_t mesh = 0;           // Scene::meshes index
    uint32_t polygon = 0;        // source polygon in that mesh
    uint32_t depth = 0;
    DVec3 normal{0.0, 0.0, 1.0}; // unit, front side
    DVec3 centroid{0.0};         // area centroid
    double area = 0.0;
    double radius = 0.0;         // max distance from centroid to a vertex
    DVec3 reflectance{0.0};      // rho
    DVec3 emission{0.0};         // emitted exitance pi * L_e (+ rho * direct punctual light), W/m^2
    DVec3 radiosity{0.0};        // B: leaves solved, inner elements the area average of their leaves
    DVec3 gathered{0.0};         // irradiance gathered through this element's own links (W/m^2)

    bool isLeaf() const { return child_count == 0; }
};

// Light flows from source to receiver: receiver.gathered += form_factor * source.radiosity.
// form_factor already includes the visibility (the unoccluded fraction).
struct Link {
    uint32_t receiver = 0;
    uint32_t source = 0;
    double form_factor = 0.0;
    float visibility = 1.0f;
    // The visibility was sampled by rays (a shadow edge may pass between them), not proven
    // by the shaft: the reconstruction (reconstruct.h) casts its own rays for it.
    bool by_rays = false;
};

// Clustering (cluster.h): a binary tree of boxes over the root elements. Links that start
// at the top cluster refine down through cluster-cluster and cluster-root links to root-root
// links (Solution::links). A link end is a node: a root element index, or a cluster index
// with kClusterNode set.
inline constexpr uint32_t kClusterNode = 0x80000000u;
inline constexpr uint32_t kNoKernel = 0xffffffffu;

struct Cluster {
    Aabb box;                   // of its members' polygons
    DVec3 centroid{0.0};        // area-weighted centroid of its members
    double area = 0.0;          // sum of its members' areas
    uint32_t parent = kNoElement;
    uint32_t first_child = kNoElement;  // two children, contiguous; kNoElement for a leaf
    uint32_t first_member = 0;  // into Solution::cluster_members (members are contiguous)
    uint32_t member_count = 0;
    bool isLeaf() const { return first_child == kNoElement; }
};

// Light from the source node's member roots to the receiver node's member roots, a point
// kernel between member centroids (cluster.cpp): small links hold the kernel per member
// pair (visibility included) at `kernel` in Solution::cluster_kernel, large ones are
// separable (kNoKernel: source weights times receiver cosines, wholly visible).
struct ClusterLink {
    uint32_t receiver = 0;          // node
    uint32_t source = 0;            // node
    uint32_t candidates = 0xffffffffu;  // potential occluders (RefineState::candidate_pool), to reopen it
    uint32_t kernel = kNoKernel;
    float visibility = 1.0f;        // 0: every sampled ray was blocked
                                    // (carries nothing); < 0: deferred, its source had no light yet
    float scale = 1.0f;             // separable links: the kernel's calibration on sampled pairs
};

struct Solution {
    std::vector<DVec3> vertices;   // element polygon loops
    // The sky's irradiance at each of `vertices` for its element's normal (W/m^2; radiosity/
    // sky_light.h), read from just inside the element; empty without a sky.
    std::vector<DVec3> vertex_sky;
    std::vector<Element> elements; // roots first (root_count of them), children appended
    uint32_t root_count = 0;
    std::vector<Link> links;       // grouped by receiver
    // Clustering (empty when SolverOptions::clustering is off or the scene has one root).
    std::vector<Cluster> clusters;            // clusters[0] is the top
    std::vector<uint32_t> cluster_members;    // root indices, in cluster order
    std::vector<uint32_t> member_position;    // per root: its index in cluster_members
    std::vector<uint32_t> root_leaf_cluster;  // per root: the leaf cluster holding it
    std::vector<ClusterLink> cluster_links;   // grouped by receiver node (roots, then clusters)
    std::vector<float> cluster_kernel;        // per small cluster link: |S| x |R| irradiance per unit B,
                                              // sparse (cluster_nodes.h: kernelMask, pairKernelOf)
    double scene_extent = 1.0;     // diagonal of the scene's bounding box (metres)
    double total_area = 0.0;
    std::unique_ptr<RayCaster> rays;  // for probes and vertex evaluation
    const Scene* scene = nullptr;     // the scene it was solved for (must outlive the Solution)
    SolverOptions options;
    SolveStats stats;

    Solution();
    ~Solution();
    Solution(Solution&&) noexcept;
    Solution& operator=(Solution&&) noexcept;
};

// Whether any light is in the solved scene: an element gives light (its radiosity holds its
// emission, with the punctual lights' and the sky's reflected direct light) or a punctual light
// or the sky can reach a probe. Without it every reading is 0, and the read-out skips its gather.
inline bool carriesLight(const Solution& s) {
    if (s.scene != nullptr && (!s.scene->lights.empty() || s.scene->sky.shines())) return true;
    for (const Element& e : s.elements)
        if (e.radiosity.x > 0.0 || e.radiosity.y > 0.0 || e.radiosity.z > 0.0) return true;
    return false;
}

}  // namespace radbake
