#pragma once
// Reading cluster-link ends (solution.h): a node is a root element index, or a cluster index
// with kClusterNode set. Shared by the solve (cluster.cpp) and the reconstruction
// (reconstruct.cpp), which must read a link exactly as the solve does.
#include <cmath>
#include <cstdint>

#include "radiosity/solution.h"

namespace radbake {

inline bool isCluster(uint32_t node) { return (node & kClusterNode) != 0; }
inline uint32_t clusterOf(uint32_t node) { return node & ~kClusterNode; }
inline uint32_t clusterNode(uint32_t cluster) { return cluster | kClusterNode; }

// A node's member roots: Solution::cluster_members[first .. first + count).
struct NodeMembers {
    uint32_t first = 0;
    uint32_t count = 0;
};

inline NodeMembers membersOf(const Solution& s, uint32_t node) {
    if (isCluster(node)) {
        const Cluster& c = s.clusters[clusterOf(node)];
        return {c.first_member, c.member_count};
    }
    return {s.member_position[node], 1};
}

// Receiver key: roots first, then clusters (the order cluster links are grouped in).
inline size_t keyOf(const Solution& s, uint32_t node) {
    return isCluster(node) ? s.root_count + clusterOf(node) : node;
}

inline DVec3 centroidOf(const Solution& s, uint32_t node) {
    return isCluster(node) ? s.clusters[clusterOf(node)].centroid : s.elements[node].centroid;
}

// Separable kernel K_ji ~ s_i r_j: the product form f(x, y) ~ f(x, c_R) f(c_S, y) / f(c_S, c_R)
// of A_i cos_i cos_j / (pi d_ij^2), first-order right in each end's extent.
// Source member i's weight towards the receiver's centroid c_R: A_i cos_i / (pi d^3).
inline double sourceWeight(const Element& i, const DVec3& c_r) {
    const DVec3 u = c_r - i.centroid;
    const double d2 = glm::dot(u, u);
    const double cos_d = glm::dot(i.normal, u);
    if (!(cos_d > 0.0) || !(d2 > 0.0)) return 0.0;
    return i.area * cos_d / (kPi * d2 * std::sqrt(d2));
}

// Receiver member j's factor: its cosine towards the source's centroid c_S, and the change of
// 1 / d^2 from (c_S, c_R) to (c_S, c_j).
inline double receiverCosine(const Element& j, const DVec3& c_s, const DVec3& c_r) {
    const DVec3 u = c_s - j.centroid;
    const double d2 = glm::dot(u, u);
    const double cos_d = glm::dot(j.normal, u);
    if (!(cos_d > 0.0) || !(d2 > 0.0)) return 0.0;
    const DVec3 w = c_s - c_r;
    return cos_d / std::sqrt(d2) * (glm::dot(w, w) / d2);
}

// A separable link's flux towards its receiver's centroid: its scale times the sum of its
// source members' weights times their radiosity (0 for pairwise or dark links).
inline DVec3 separableFlux(const Solution& s, const ClusterLink& link) {
    if (link.kernel != kNoKernel || !(link.visibility > 0.0f)) return DVec3(0.0);
    const NodeMembers sm = membersOf(s, link.source);
    const DVec3 c_r = centroidOf(s, link.receiver);
    DVec3 flux(0.0);
    for (uint32_t k = sm.first; k < sm.first + sm.count; ++k) {
        const Element& e = s.elements[s.cluster_members[k]];
        flux += sourceWeight(e, c_r) * e.radiosity;
    }
    return double(link.scale) * flux;
}

}  // namespace radbake
