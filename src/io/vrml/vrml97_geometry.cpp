// IndexedFaceSet, ElevationGrid and Extrusion -> object-space meshes.
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>

#include "io/vrml/vrml97_builder.h"
#include "io/vrml/vrml97_parser.h"
#include "scene/triangulate.h"

namespace radbake::vrml {
namespace {

Vec3 colorAt(const std::vector<float>& colors, size_t i) {
    return Vec3(colors[3 * i], colors[3 * i + 1], colors[3 * i + 2]);
}

// Appends the triangles of one polygon and numbers them as the next polygon.
size_t addPolygon(Mesh& mesh, std::span<const uint32_t> loop, bool convex) {
    const size_t count = triangulatePolygon(mesh.positions, loop, convex, mesh.triangles);
    if (count == 0) return 0;
    mesh.triangle_polygon.insert(mesh.triangle_polygon.end(), count, mesh.polygon_count);
    ++mesh.polygon_count;
    return count;
}

}  // namespace

bool Vrml97Builder::indexedFaceSet(const Node& node, Mesh& mesh) {
    const NodePtr coord = sfNode(node, "coord");
    if (!coord) return false;
    const std::vector<float>& points = mfFloats(*coord, "point");
    const std::vector<int32_t>& coord_index = mfInts(node, "coordIndex");
    const size_t point_count = points.size() / 3;
    if (coord_index.empty() || point_count == 0) return false;

    const bool ccw = sfBool(node, "ccw", true);
    const bool convex = sfBool(node, "convex", true);
    mesh.solid = sfBool(node, "solid", true);
    mesh.crease_angle = sfFloat(node, "creaseAngle", 0.0f);

    // Colours: per vertex (through colorIndex, or coordIndex when it is empty) or per face.
    const NodePtr color_node = sfNode(node, "color");
    const std::vector<float>* colors = color_node ? &mfFloats(*color_node, "color") : nullptr;
    const size_t color_count = colors ? colors->size() / 3 : 0;
    const bool color_per_vertex = sfBool(node, "colorPerVertex", true);
    const std::vector<int32_t>& color_index = mfInts(node, "colorIndex");
    if (colors && color_count == 0) colors = nullptr;
    if (colors) {
        // Drop colours whose indices do not fit rather than guess.
        bool fits = true;
        if (!color_index.empty()) {
            for (int32_t i : color_index) fits = fits && (i < 0 ? color_per_vertex : static_cast<size_t>(i) < color_count);
            if (color_per_vertex && color_index.size() < coord_index.size()) fits = false;
        } else if (color_per_vertex) {
            for (int32_t i : coord_index) fits = fits && (i < 0 || static_cast<size_t>(i) < color_count);
        }
        if (!fits) {
            diagnostics_.warning(node.location, "IndexedFaceSet colours do not match its faces; colours ignored");
            colors = nullptr;
        }
    }
    const bool corner_colors = colors && color_per_vertex && !color_index.empty();

    // Texture coordinates: per corner through texCoordIndex, or per coordinate when it is empty.
    const NodePtr tex_node = sfNode(node, "texCoord");
    const std::vector<float>* tex = tex_node ? &mfFloats(*tex_node, "point") : nullptr;
    const size_t tex_count = tex ? tex->size() / 2 : 0;
    const std::vector<int32_t>& tex_index = mfInts(node, "texCoordIndex");
    if (tex && tex_count == 0) tex = nullptr;
    if (tex) {
        bool fits = tex_index.empty() || tex_index.size() >= coord_index.size();
        for (size_t k = 0; fits && k < coord_index.size(); ++k) {
            if (coord_index[k] < 0) continue;
            const int32_t i = tex_index.empty() ? coord_index[k] : tex_index[k];
            fits = i >= 0 && static_cast<size_t>(i) < tex_count;
        }
        if (!fits) {
            diagnostics_.warning(node.location, "IndexedFaceSet texture coordinates do not match its faces; ignored");
            tex = nullptr;
        }
    }
    const bool corner_uvs = tex && !tex_index.empty();
    auto uvAt = [&](size_t i) { return Vec2((*tex)[2 * i], (*tex)[2 * i + 1]); };

    // Normals are kept only in the common per-coordinate form.
    const NodePtr normal_node = sfNode(node, "normal");
    const std::vector<float>* normals = normal_node ? &mfFloats(*normal_node, "vector") : nullptr;
    if (normals && (!sfBool(node, "normalPerVertex", true) || !mfInts(node, "normalIndex").empty() ||
                    normals->size() / 3 < point_count))
        normals = nullptr;
    if (corner_colors) normals = nullptr;

    // Only referenced coordinates become vertices (a Coordinate node is often shared).
    // A corner with its own colour or texture coordinate is its own vertex.
    std::vector<uint32_t> remap;
    std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> corner_vertex;
    const bool per_corner = corner_colors || corner_uvs;
    if (!per_corner) remap.assign(point_count, UINT32_MAX);
    auto vertexFor = [&](uint32_t p, size_t corner) -> uint32_t {
        uint32_t* slot;
        if (per_corner) {
            const auto key = std::make_tuple(p, corner_colors ? uint32_t(color_index[corner]) : 0u,
                                             corner_uvs ? uint32_t(tex_index[corner]) : 0u);
            slot = &corner_vertex.try_emplace(key, UINT32_MAX).first->second;
        } else {
            slot = &remap[p];
        }
        if (*slot == UINT32_MAX) {
            *slot = static_cast<uint32_t>(mesh.positions.size());
            mesh.positions.emplace_back(points[3 * p], points[3 * p + 1], points[3 * p + 2]);
            if (normals) mesh.normals.push_back(colorAt(*normals, p));
            if (colors && color_per_vertex)
                mesh.vertex_colors.push_back(colorAt(*colors, corner_colors ? size_t(color_index[corner]) : p));
            if (tex) mesh.uv0.push_back(uvAt(corner_uvs ? size_t(tex_index[corner]) : p));
        }
        return *slot;
    };

    size_t short_faces = 0, bad_faces = 0, face = 0;
    size_t start = 0;
    const size_t n = coord_index.size();
    while (start < n) {
        size_t end = start;
        bool in_range = true;
        while (end < n && coord_index[end] >= 0) {
            in_range = in_range && static_cast<size_t>(coord_index[end]) < point_count;
            ++end;
        }
        const size_t corners = end - start;
        if (corners < 3) {
            if (corners > 0) ++short_faces;
        } else if (!in_range) {
            ++bad_faces;
        } else {
            loop_.clear();
            for (size_t k = start; k < end; ++k) loop_.push_back(vertexFor(static_cast<uint32_t>(coord_index[k]), k));
            if (!ccw) std::reverse(loop_.begin(), loop_.end());
            if (addPolygon(mesh, loop_, convex) > 0 && colors && !color_per_vertex) {
                const size_t c = color_index.empty() ? face : size_t(std::max(color_index[std::min(face, color_index.size() - 1)], 0));
                mesh.polygon_colors.push_back(c < color_count ? colorAt(*colors, c) : Vec3(1.0f));
            }
        }
        if (corners > 0 || end < n) ++face;
        start = end + 1;
    }
    if (short_faces || bad_faces) {
        std::string message = "IndexedFaceSet: dropped";
        if (short_faces) message += " " + std::to_string(short_faces) + " faces with fewer than 3 points";
        if (short_faces && bad_faces) message += " and";
        if (bad_faces) message += " " + std::to_string(bad_faces) + " faces with indices beyond its " +
                                  std::to_string(point_count) + " points";
        diagnostics_.warning(node.location, message);
    }
    return mesh.polygon_count > 0;
}

bool Vrml97Builder::elevationGrid(const Node& node, Mesh& mesh) {
    const int64_t nx = sfInt(node, "xDimension", 0), nz = sfInt(node, "zDimension", 0);
    const std::vector<float>& height = mfFloats(node, "height");
    if (nx < 2 || nz < 2) return false;
    if (static_cast<double>(nx) * static_cast<double>(nz) > static_cast<double>(height.size())) {
        diagnostics_.warning(node.location, "ElevationGrid has " + std::to_string(height.size()) +
                                                " heights for a " + std::to_string(nx) + " x " + std::to_string(nz) +
                                                " grid; ignored");
        return false;
    }
    const float dx = sfFloat(node, "xSpacing", 1.0f), dz = sfFloat(node, "zSpacing", 1.0f);
    const bool ccw = sfBool(node, "ccw", true);
    mesh.solid = sfBool(node, "solid", true);
    mesh.crease_angle = sfFloat(node, "creaseAngle", 0.0f);
    for (int64_t j = 0; j < nz; ++j)
        for (int64_t i = 0; i < nx; ++i)
            mesh.positions.emplace_back(float(i) * dx, height[size_t(i + j * nx)], float(j) * dz);

    const NodePtr color_node = sfNode(node, "color");
    const std::vector<float>* colors = color_node ? &mfFloats(*color_node, "color") : nullptr;
    const bool per_vertex = sfBool(node, "colorPerVertex", true);
    const size_t needed = per_vertex ? size_t(nx * nz) : size_t((nx - 1) * (nz - 1));
    if (colors && colors->size() / 3 < needed) {
        diagnostics_.warning(node.location, "ElevationGrid has too few colours; colours ignored");
        colors = nullptr;
    }
    if (colors && per_vertex)
        for (size_t v = 0; v < needed; ++v) mesh.vertex_colors.push_back(colorAt(*colors, v));

    // Texture coordinates per grid point: texCoord's, else the default (ISO/IEC 14772-1 6.15:
    // s from 0 to 1 along x, t along z).
    const NodePtr tex_node = sfNode(node, "texCoord");
    const std::vector<float>* tex = tex_node ? &mfFloats(*tex_node, "point") : nullptr;
    if (tex && tex->size() / 2 < size_t(nx * nz)) {
        diagnostics_.warning(node.location, "ElevationGrid has too few texture coordinates; the default ones are used");
        tex = nullptr;
    }
    for (int64_t j = 0; j < nz; ++j)
        for (int64_t i = 0; i < nx; ++i) {
            const size_t v = size_t(i + j * nx);
            mesh.uv0.push_back(tex ? Vec2((*tex)[2 * v], (*tex)[2 * v + 1])
                                   : Vec2(float(i) / float(nx - 1), float(j) / float(nz - 1)));
        }

    // (i,j) (i,j+1) (i+1,j+1) (i+1,j) runs counter-clockwise seen from +Y.
    for (int64_t j = 0; j + 1 < nz; ++j)
        for (int64_t i = 0; i + 1 < nx; ++i) {
            loop_ = {uint32_t(i + j * nx), uint32_t(i + (j + 1) * nx), uint32_t(i + 1 + (j + 1) * nx),
                     uint32_t(i + 1 + j * nx)};
            if (!ccw) std::reverse(loop_.begin(), loop_.end());
            if (addPolygon(mesh, loop_, true) > 0 && colors && !per_vertex)
                mesh.polygon_colors.push_back(colorAt(*colors, size_t(i + j * (nx - 1))));
        }
    return mesh.polygon_count > 0;
}

namespace {

// Spine-aligned cross-section planes (ISO/IEC 14772-1 6.18): per spine point, the X, Y, Z
// axes the cross-section is placed in.
struct SpineFrame {
    DVec3 x, y, z;
};

// The shortest rotation taking +Y to the unit vector `y`.
glm::dquat rotateUpTo(const DVec3& y) {
    const DVec3 up(0.0, 1.0, 0.0);
    const double c = glm::clamp(glm::dot(up, y), -1.0, 1.0);
    const DVec3 axis = glm::cross(up, y);
    const double s = glm::length(axis);
    if (s < 1e-12) return c > 0.0 ? glm::dquat(1.0, 0.0, 0.0, 0.0) : glm::angleAxis(kPi, DVec3(1.0, 0.0, 0.0));
    return glm::angleAxis(std::atan2(s, c), axis / s);
}

std::vector<SpineFrame> spineFrames(const std::vector<DVec3>& spine) {
    const size_t n = spine.size();
    const bool closed = n > 2 && spine.front() == spine.back();
    std::vector<SpineFrame> frames(n);
    auto normalized = [](DVec3 v) {
        const double length = glm::length(v);
        return length > 1e-12 && std::isfinite(length) ? v / length : DVec3(0.0);
    };
    for (size_t i = 0; i < n; ++i) {
        DVec3 y;
        if (i == 0) y = closed ? spine[1] - spine[n - 2] : spine[1] - spine[0];
        else if (i == n - 1) y = closed ? spine[1] - spine[n - 2] : spine[n - 1] - spine[n - 2];
        else y = spine[i + 1] - spine[i - 1];
        frames[i].y = normalized(y);
        DVec3 z(0.0);
        if (i > 0 && i + 1 < n) z = glm::cross(spine[i + 1] - spine[i], spine[i - 1] - spine[i]);
        else if (closed) z = glm::cross(spine[1] - spine[0], spine[n - 2] - spine[0]);
        frames[i].z = normalized(z);
    }
    if (!closed && n > 2) {
        frames[0].z = frames[1].z;
        frames[n - 1].z = frames[n - 2].z;
    }
    // Collinear stretches take the previous Z; consecutive Zs must not flip.
    bool any_z = false;
    for (size_t i = 0; i < n; ++i) {
        if (frames[i].z == DVec3(0.0)) {
            if (i > 0) frames[i].z = frames[i - 1].z;
        } else {
            if (i > 0 && frames[i - 1].z != DVec3(0.0) && glm::dot(frames[i].z, frames[i - 1].z) < 0.0)
                frames[i].z = -frames[i].z;
            any_z = true;
        }
    }
    // A straight spine: rotate the default frame so that +Y follows the spine.
    DVec3 first_y(0.0, 1.0, 0.0);
    for (const SpineFrame& f : frames)
        if (f.y != DVec3(0.0)) {
            first_y = f.y;
            break;
        }
    for (size_t i = 0; i < n; ++i) {
        if (frames[i].y == DVec3(0.0)) frames[i].y = i > 0 ? frames[i - 1].y : first_y;
        if (!any_z || frames[i].z == DVec3(0.0)) {
            frames[i].z = rotateUpTo(frames[i].y) * DVec3(0.0, 0.0, 1.0);
        }
        frames[i].x = normalized(glm::cross(frames[i].y, frames[i].z));
    }
    return frames;
}

}  // namespace

bool Vrml97Builder::extrusion(const Node& node, Mesh& mesh) {
    std::vector<float> cross = mfFloats(node, "crossSection");
    if (!node.field("crossSection")) cross = {1, 1, 1, -1, -1, -1, -1, 1, 1, 1};
    std::vector<float> spine_values = mfFloats(node, "spine");
    if (!node.field("spine")) spine_values = {0, 0, 0, 0, 1, 0};
    const std::vector<float>& scales = mfFloats(node, "scale");
    const std::vector<float>& orientations = mfFloats(node, "orientation");
    const size_t nc = cross.size() / 2, ns = spine_values.size() / 3;
    if (nc < 2 || ns < 2) return false;
    if (double(nc) * double(ns) > double(vrml97Limits().max_triangles)) return false;
    const bool ccw = sfBool(node, "ccw", true), convex = sfBool(node, "convex", true);
    mesh.solid = sfBool(node, "solid", true);
    mesh.crease_angle = sfFloat(node, "creaseAngle", 0.0f);

    std::vector<DVec3> spine(ns);
    for (size_t i = 0; i < ns; ++i) spine[i] = DVec3(spine_values[3 * i], spine_values[3 * i + 1], spine_values[3 * i + 2]);
    const std::vector<SpineFrame> frames = spineFrames(spine);
    for (size_t i = 0; i < ns; ++i) {
        // scale and orientation: one value for all, or one per spine point
        const size_t si = scales.size() >= 2 * ns ? i : 0, oi = orientations.size() >= 4 * ns ? i : 0;
        const DVec2 s = scales.size() >= 2 ? DVec2(scales[2 * si], scales[2 * si + 1]) : DVec2(1.0);
        glm::dquat q(1.0, 0.0, 0.0, 0.0);
        if (orientations.size() >= 4) {
            const DVec3 axis(orientations[4 * oi], orientations[4 * oi + 1], orientations[4 * oi + 2]);
            const double length = glm::length(axis);
            if (length > 0.0 && std::isfinite(length)) q = glm::angleAxis(double(orientations[4 * oi + 3]), axis / length);
        }
        const glm::dmat3 frame(frames[i].x, frames[i].y, frames[i].z);
        for (size_t j = 0; j < nc; ++j) {
            const DVec3 local = q * DVec3(s.x * cross[2 * j], 0.0, s.y * cross[2 * j + 1]);
            mesh.positions.push_back(Vec3(spine[i] + frame * local));
        }
    }
    auto at = [&](size_t i, size_t j) { return uint32_t(i * nc + j); };
    // Sides: (i,j) (i,j+1) (i+1,j+1) (i+1,j) faces outward for the default square section.
    for (size_t i = 0; i + 1 < ns; ++i)
        for (size_t j = 0; j + 1 < nc; ++j) {
            loop_ = {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)};
            if (!ccw) std::reverse(loop_.begin(), loop_.end());
            addPolygon(mesh, loop_, true);
        }
    // Caps: the section itself (without its closing repeat), reversed at the beginning.
    const bool closed_section = nc > 2 && cross[0] == cross[2 * (nc - 1)] && cross[1] == cross[2 * (nc - 1) + 1];
    const size_t cap_count = closed_section ? nc - 1 : nc;
    if (cap_count >= 3) {
        for (int end = 0; end < 2; ++end) {
            if (!sfBool(node, end == 0 ? "beginCap" : "endCap", true)) continue;
            const size_t i = end == 0 ? 0 : ns - 1;
            loop_.clear();
            for (size_t j = 0; j < cap_count; ++j) loop_.push_back(at(i, j));
            if ((end == 0) == ccw) std::reverse(loop_.begin(), loop_.end());
            addPolygon(mesh, loop_, convex);
        }
    }
    return mesh.polygon_count > 0;
}

}  // namespace radbake::vrml

namespace radbake::vrml {

void defaultTextureCoordinates(Mesh& mesh) {
    // ISO/IEC 14772-1 6.23: s along the bounding box's longest side from 0 to 1, t along the
    // next longest from 0 to its length over the longest; ties go to X, then Y, then Z.
    if (mesh.positions.empty()) return;
    DVec3 lo(mesh.positions.front()), hi(lo);
    for (const Vec3& p : mesh.positions) {
        lo = glm::min(lo, DVec3(p));
        hi = glm::max(hi, DVec3(p));
    }
    const DVec3 size = hi - lo;
    int axes[3] = {0, 1, 2};
    std::stable_sort(axes, axes + 3, [&](int a, int b) { return size[a] > size[b]; });
    const double longest = size[axes[0]];
    if (!(longest > 0.0)) return;
    mesh.uv0.clear();
    for (const Vec3& p : mesh.positions)
        mesh.uv0.emplace_back(static_cast<float>((p[axes[0]] - lo[axes[0]]) / longest),
                              static_cast<float>((p[axes[1]] - lo[axes[1]]) / longest));
}

}  // namespace radbake::vrml
