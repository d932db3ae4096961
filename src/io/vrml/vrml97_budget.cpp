// The VRML97 builder's memory budget: a scene graph's expansion (DEF/USE fan-out, PROTO
// instances, Extrusions, primitives) estimated from its fields before any mesh is built, so a
// small file that expands to gigabytes is a located error, not an allocation failure.
#include <algorithm>
#include <cstdio>

#include "io/vrml/primitives.h"
#include "io/vrml/vrml97_builder.h"
#include "io/vrml/vrml97_parser.h"

namespace radbake::vrml {
namespace {

struct PrimitiveSize {
    double vertices = 0.0, triangles = 0.0;
};

PrimitiveSize sizeOf(const Mesh& mesh) {
    return {static_cast<double>(mesh.positions.size()), static_cast<double>(mesh.triangles.size())};
}

// Each primitive's tessellation, measured once by building it (so it never disagrees with primitives.cpp).
PrimitiveSize primitiveSize(const std::string& type) {
    static const PrimitiveSize box = [] { Mesh m; appendBox(m, Vec3(1.0f)); return sizeOf(m); }();
    static const PrimitiveSize sphere = [] { Mesh m; appendSphere(m, 1.0f); return sizeOf(m); }();
    static const PrimitiveSize cylinder = [] {
        Mesh m;
        appendCylinder(m, 1.0f, 1.0f, true, true, true);
        return sizeOf(m);
    }();
    static const PrimitiveSize cone = [] { Mesh m; appendCone(m, 1.0f, 1.0f, true, true); return sizeOf(m); }();
    if (type == "Box") return box;
    if (type == "Sphere") return sphere;
    if (type == "Cylinder") return cylinder;
    if (type == "Cone") return cone;
    return {};
}

std::string describeNode(const Node& node) {
    return node.name.empty() ? node.type : node.type + " '" + node.name + "'";
}

}  // namespace

Vrml97Builder::Expansion Vrml97Builder::geometryExpansion(const Node& geometry) const {
    double vertices = 0.0, triangles = 0.0;
    const std::string& type = geometry.type;
    if (type == "IndexedFaceSet") {
        // At most a vertex and a triangle per index (a face of k corners makes k - 2 triangles).
        vertices = triangles = static_cast<double>(mfInts(geometry, "coordIndex").size());
    } else if (type == "ElevationGrid") {
        const double nx = std::max(sfInt(geometry, "xDimension", 0), 0);
        const double nz = std::max(sfInt(geometry, "zDimension", 0), 0);
        vertices = nx * nz;
        triangles = 2.0 * std::max(nx - 1.0, 0.0) * std::max(nz - 1.0, 0.0);
    } else if (type == "Extrusion") {
        // The spine x cross-section grid, two triangles a side quad, and the two caps.
        const double nc = geometry.field("crossSection") ? double(mfFloats(geometry, "crossSection").size() / 2) : 5.0;
        const double ns = geometry.field("spine") ? double(mfFloats(geometry, "spine").size() / 3) : 2.0;
        vertices = nc * ns;
        triangles = 2.0 * std::max(ns - 1.0, 0.0) * std::max(nc - 1.0, 0.0) + 2.0 * nc;
    } else {
        const PrimitiveSize size = primitiveSize(type);
        vertices = size.vertices;
        triangles = size.triangles;
    }
    if (triangles <= 0.0) return {};
    return {1.0, triangles, meshBytesEstimate(vertices, triangles)};
}

// The children visit() walks (the chosen Switch choice, LOD's first level).
std::vector<NodePtr> Vrml97Builder::expandedChildren(const Node& node) const {
    const std::string& type = node.type;
    if (type == "Transform" || type == "Group" || type == "Collision" || type == "Billboard" || type == "Anchor") {
        const FieldValue* children = node.field("children");
        return children ? children->nodes : std::vector<NodePtr>{};
    }
    if (type == "Switch") {
        const int32_t which = sfInt(node, "whichChoice", -1);
        const FieldValue* choice = node.field("choice");
        if (choice && which >= 0 && static_cast<size_t>(which) < choice->nodes.size())
            return {choice->nodes[static_cast<size_t>(which)]};
    }
    if (type == "LOD") {
        const FieldValue* level = node.field("level");
        if (level && !level->nodes.empty()) return {level->nodes.front()};
    }
    return {};
}

// Memoised per node, so a DEF used a million times is sized once: linear in the file.
Vrml97Builder::Expansion Vrml97Builder::expansionOf(const NodePtr& start, int depth) {
    if (!start || aborted_ || depth > 4 * vrml97Limits().max_nesting) return {};
    const NodePtr node = resolve(start);
    if (!node) return {};
    if (const auto it = expansions_.find(node.get()); it != expansions_.end()) return it->second;
    Expansion total;
    if (node->type == "Shape") {
        if (const NodePtr geometry = sfNode(*node, "geometry")) total = geometryExpansion(*geometry);
    } else {
        for (const NodePtr& child : expandedChildren(*node)) total.add(expansionOf(child, depth + 1));
    }
    expansions_[node.get()] = total;
    return total;
}

bool Vrml97Builder::expansionFits(const std::vector<NodePtr>& roots) {
    if (!options_.memory) return true;
    std::vector<Expansion> sizes;
    Expansion total;
    for (const NodePtr& root : roots) {
        sizes.push_back(expansionOf(root, 0));
        total.add(sizes.back());
    }
    if (aborted_) return false;
    if (options_.memory->fits(total.bytes)) return true;
    reportExpansion(roots, sizes);
    return false;
}

// Names the smallest node that alone expands past the budget (the DEF a fan-out USEs, the
// Extrusion), else the top-level node where the file's sum passes it.
void Vrml97Builder::reportExpansion(const std::vector<NodePtr>& roots, const std::vector<Expansion>& sizes) {
    const MemoryGauge& memory = *options_.memory;
    const double room = memory.roomBytes();
    Expansion sum;
    size_t first = 0;
    for (; first < roots.size(); ++first) {
        sum.add(sizes[first]);
        if (sum.bytes > room) break;
    }
    first = std::min(first, roots.size() - 1);
    const auto largest = std::max_element(sizes.begin(), sizes.end(),
                                          [](const Expansion& a, const Expansion& b) { return a.bytes < b.bytes; });
    if (largest->bytes <= room) {
        abort(roots[first]->location, overBudgetMessage("the file, up to this node,", sum.meshes, sum.triangles,
                                                        sum.bytes, memory));
        return;
    }
    NodePtr node = resolve(roots[static_cast<size_t>(largest - sizes.begin())]);
    Expansion size = *largest;
    for (;;) {
        if (node->type == "Shape") {
            const NodePtr geometry = sfNode(*node, "geometry");
            if (geometry) node = geometry;
            break;
        }
        NodePtr next;
        for (const NodePtr& child : expandedChildren(*node)) {
            const NodePtr resolved = resolve(child);
            if (!resolved) continue;
            const auto it = expansions_.find(resolved.get());
            if (it != expansions_.end() && it->second.bytes > room) {
                next = resolved;
                size = it->second;
                break;
            }
        }
        if (!next) break;
        node = next;
    }
    abort(node->location, overBudgetMessage(describeNode(*node), size.meshes, size.triangles, size.bytes, memory));
}

// The running account, for what the estimate cannot see (Inlines read once per USE).
bool Vrml97Builder::reserveMesh(const Mesh& mesh, const Node& geometry) {
    if (!options_.memory) return true;
    const double bytes = meshBytesEstimate(double(mesh.positions.size()), double(mesh.triangles.size()));
    if (options_.memory->reserve(bytes)) return true;
    char counts[96];
    std::snprintf(counts, sizeof counts, "%zu triangles in %zu meshes", triangles_, scene_.meshes.size() + 1);
    abort(geometry.location, "the scene's meshes outgrow the memory budget at this " + describeNode(geometry) + " (" +
                                 counts + " so far; --max-memory " +
                                 bytesText(options_.memory->budgetMegabytes() * 1048576.0) + ")");
    return false;
}

}  // namespace radbake::vrml
