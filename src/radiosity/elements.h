#pragma once
// The element hierarchy: root elements from the scene's source polygons, and the split rule
// that makes children. Geometry of elements is computed in double from the scene's floats.
#include <span>
#include <vector>

#include "radiosity/solution.h"

namespace radbake {

// A borrowed view of an element's polygon (convex, counter-clockwise around `normal`).
struct PolygonView {
    std::span<const DVec3> vertices;
    DVec3 normal{0.0, 0.0, 1.0};
    DVec3 centroid{0.0};
    double radius = 0.0;
};

inline PolygonView polygonOf(const Solution& solution, const Element& element) {
    return {std::span<const DVec3>(solution.vertices.data() + element.first_vertex, element.vertex_count),
            element.normal, element.centroid, element.radius};
}

// Appends one root element per convex planar source polygon (or per triangle of a polygon
// that is not convex and planar), front side = counter-clockwise side. Degenerate polygons
// are skipped. Fills scene_extent, total_area and root_count.
void buildRootElements(const Scene& scene, Solution& solution);

// The child loops of a convex polygon: a triangle or n-gon gives n quads (vertex, edge
// midpoint, centre, edge midpoint); a quad gives 4 such quads, or 2 halves across its long
// direction when it is more than twice as long as wide (keeps elements well shaped).
std::vector<std::vector<DVec3>> splitPolygon(std::span<const DVec3> loop);

// Creates the children of element `index` if it has none yet; returns its child count.
// Not thread-safe (the caller splits sequentially in a fixed order for determinism).
uint32_t ensureChildren(Solution& solution, uint32_t index);

// Fills normal, centroid, area and radius of an element from its loop.
void setElementGeometry(Element& element, std::span<const DVec3> loop);

}  // namespace radbake
