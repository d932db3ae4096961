#pragma once
// Reading cluster-link ends (solution.h): a node is a root element index, or a cluster index
// with kClusterNode set. Shared by the solve (cluster.cpp) and the reconstruction
// (reconstruct.cpp), which must read a link exactly as the solve does.
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

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

// A pairwise link's kernel, stored sparse at Solution::cluster_kernel[link.kernel ...]: the bits
// of a 64-bit mask of the member pairs p = i * |R| + j that carry light (in two floats), then
// those pairs' values in pair order (about half the pairs of a building's links carry none).
inline constexpr size_t kKernelMaskFloats = 2;
static_assert(kKernelMaskFloats * sizeof(float) == sizeof(uint64_t));

inline uint64_t kernelMask(const Solution& s, const ClusterLink& link) {
    uint64_t mask = 0;
    std::memcpy(&mask, s.cluster_kernel.data() + link.kernel, sizeof mask);
    return mask;
}

// Floats a pairwise link's kernel takes.
inline size_t kernelFloats(uint64_t mask) { return kKernelMaskFloats + size_t(std::popcount(mask)); }

// A pair's value in a sparse kernel: its mask and the values that follow it.
inline double kernelValue(uint64_t mask, const float* values, uint32_t pair) {
    if (!((mask >> pair) & 1u)) return 0.0;
    return values[std::popcount(mask & ((uint64_t(1) << pair) - 1u))];
}

// The values of a pairwise link's kernel (after its mask).
inline const float* kernelValues(const Solution& s, const ClusterLink& link) {
    return s.cluster_kernel.data() + link.kernel + kKernelMaskFloats;
}

// Irradiance at receiver member j per unit radiosity of source member i, pair = i * |R| + j.
inline double pairKernelOf(const Solution& s, const ClusterLink& link, uint32_t pair) {
    return kernelValue(kernelMask(s, link), kernelValues(s, link), pair);
}

// Appends a dense kernel (|S| x |R| values, at most 64) in the sparse form; returns its offset.
inline uint32_t appendKernel(Solution& s, const float* dense, size_t pairs) {
    const auto offset = static_cast<uint32_t>(s.cluster_kernel.size());
    uint64_t mask = 0;
    for (size_t p = 0; p < pairs; ++p)
        if (dense[p] > 0.0f) mask |= uint64_t(1) << p;
    float bits[kKernelMaskFloats];
    std::memcpy(bits, &mask, sizeof mask);
    s.cluster_kernel.insert(s.cluster_kernel.end(), bits, bits + kKernelMaskFloats);
    for (size_t p = 0; p < pairs; ++p)
        if (dense[p] > 0.0f) s.cluster_kernel.push_back(dense[p]);
    return offset;
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
