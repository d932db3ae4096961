// Scene validation: the last stop before any later stage sees the scene. Bad numbers are
// located errors; bad or useless geometry is dropped and counted, one warning per mesh.
#include "scene/validate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "scene/validate_overlap.h"

namespace radbake {
namespace validation {

std::string describeMesh(const Mesh& mesh, size_t index) {
    return mesh.name.empty() ? "mesh #" + std::to_string(index) : "mesh '" + mesh.name + "'";
}

double sceneExtent(const std::vector<Mesh>& meshes) {
    DVec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    double magnitude = 0.0;
    for (const Mesh& mesh : meshes)
        for (const Vec3& p : mesh.positions) {
            const DVec3 q(p);
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
            magnitude = std::max({magnitude, std::abs(q.x), std::abs(q.y), std::abs(q.z)});
        }
    if (lo.x > hi.x) return 0.0;
    return std::max(magnitude, glm::length(hi - lo));
}

}  // namespace validation

namespace {

using validation::describeMesh;
using validation::sceneExtent;

// Reflectance must stay below 1 or the radiosity system does not converge.
constexpr float kMaxReflectance = 0.999f;

// Positions are floats; a coordinate of magnitude up to E (the scene's extent) is rounded by
// up to E * 2^-24. A triangle whose smallest height is below a few such steps has no
// reliable plane or area: it is degenerate at this scene's precision.
constexpr double kFloatStep = 1.0 / 16777216.0;  // 2^-24
constexpr double kDegenerateHeightSteps = 4.0;

std::string quoted(const std::string& name) { return "'" + name + "'"; }

std::string describeMaterial(const Material& material, size_t index) {
    return material.name.empty() ? "material #" + std::to_string(index) : "material " + quoted(material.name);
}

const char* lightKind(LightType type) {
    switch (type) {
        case LightType::Point: return "point light";
        case LightType::Spot: return "spot light";
        case LightType::Directional: return "directional light";
    }
    return "light";
}

bool finite(float value) { return std::isfinite(value); }

std::string vecText(const Vec3& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

// ---------------------------------------------------------------------------------------
// Materials, lights, cameras.

// `factor_only`: every polygon of every mesh using the material has its own reflectance (a
// texture set it), so the material's colour is only the factor that multiplies the texture
// (MTL's `Kd 1` with a map_Kd) and is kept as given.
bool validateMaterial(Material& material, size_t index, bool factor_only, Diagnostics& diagnostics) {
    const std::string what = describeMaterial(material, index);
    if (!isFinite(material.reflectance) || !isFinite(material.emission) || !finite(material.transparency) ||
        !finite(material.ambient_intensity)) {
        diagnostics.error(material.location, what + " has a non-finite colour or value");
        return false;
    }
    if (factor_only) {
        material.reflectance = glm::max(material.reflectance, Vec3(0.0f));
        material.emission = glm::max(material.emission, Vec3(0.0f));
        return true;
    }
    const Vec3 clamped = glm::clamp(material.reflectance, Vec3(0.0f), Vec3(kMaxReflectance));
    if (glm::any(glm::lessThan(material.reflectance, Vec3(0.0f))))
        diagnostics.warning(material.location, what + " has negative reflectance " + vecText(material.reflectance) +
                                                   ", clamped to 0");
    if (glm::any(glm::greaterThanEqual(material.reflectance, Vec3(1.0f))))
        diagnostics.warning(material.location, what + " has reflectance " + vecText(material.reflectance) +
                                                   " >= 1, clamped to " + std::to_string(kMaxReflectance));
    material.reflectance = clamped;
    if (glm::any(glm::lessThan(material.emission, Vec3(0.0f)))) {
        diagnostics.warning(material.location,
                            what + " has negative emission " + vecText(material.emission) + ", clamped to 0");
        material.emission = glm::max(material.emission, Vec3(0.0f));
    }
    return true;
}

bool validateLight(const Light& light, size_t index, Diagnostics& diagnostics) {
    // An unbounded radius is legitimate (formats without a light range); NaN is not.
    const bool ok = isFinite(light.position) && isFinite(light.direction) && isFinite(light.color) &&
                    finite(light.intensity) && finite(light.ambient_intensity) && isFinite(light.attenuation) &&
                    !std::isnan(light.radius) && finite(light.beam_width) && finite(light.cut_off_angle) &&
                    finite(light.angular_diameter);
    if (!ok)
        diagnostics.error(light.location,
                          std::string(lightKind(light.type)) + " #" + std::to_string(index) + " has a non-finite value");
    return ok;
}

bool validateCamera(const Camera& camera, size_t index, Diagnostics& diagnostics) {
    const bool ok = isFinite(camera.position) && std::isfinite(camera.orientation.x) &&
                    std::isfinite(camera.orientation.y) && std::isfinite(camera.orientation.z) &&
                    std::isfinite(camera.orientation.w) && finite(camera.field_of_view);
    if (!ok)
        diagnostics.error(camera.location, "camera " + (camera.name.empty() ? "#" + std::to_string(index)
                                                                            : quoted(camera.name)) +
                                               " has a non-finite value");
    return ok;
}

// ---------------------------------------------------------------------------------------
// Meshes.

// Errors that make the mesh unusable. Reported once per mesh, naming the first bad vertex.
bool checkMeshNumbers(const Mesh& mesh, size_t index, size_t material_count, Diagnostics& diagnostics) {
    const std::string what = describeMesh(mesh, index);
    bool ok = true;
    auto firstBad = [](const std::vector<Vec3>& values, size_t& bad_count) {
        size_t first = values.size();
        bad_count = 0;
        for (size_t i = 0; i < values.size(); ++i)
            if (!isFinite(values[i])) {
                if (first == values.size()) first = i;
                ++bad_count;
            }
        return first;
    };
    size_t bad = 0;
    if (size_t first = firstBad(mesh.positions, bad); bad > 0) {
        diagnostics.error(mesh.location, what + ": " + std::to_string(bad) + " vertex position(s) not finite (first: vertex " +
                                             std::to_string(first) + ")");
        ok = false;
    }
    if (size_t first = firstBad(mesh.vertex_colors, bad); bad > 0) {
        diagnostics.error(mesh.location, what + ": " + std::to_string(bad) + " vertex colour(s) not finite (first: vertex " +
                                             std::to_string(first) + ")");
        ok = false;
    }
    if (size_t first = firstBad(mesh.polygon_colors, bad); bad > 0) {
        diagnostics.error(mesh.location, what + ": " + std::to_string(bad) +
                                             " polygon colour(s) not finite (first: polygon " + std::to_string(first) + ")");
        ok = false;
    }
    const size_t bad_uv = static_cast<size_t>(std::count_if(mesh.uv0.begin(), mesh.uv0.end(), [](const Vec2& uv) {
        return !std::isfinite(uv.x) || !std::isfinite(uv.y);
    }));
    if (bad_uv > 0) {
        const size_t first = static_cast<size_t>(std::find_if(mesh.uv0.begin(), mesh.uv0.end(), [](const Vec2& uv) {
                                                     return !std::isfinite(uv.x) || !std::isfinite(uv.y);
                                                 }) - mesh.uv0.begin());
        diagnostics.error(mesh.location, what + ": " + std::to_string(bad_uv) + " texture coordinate(s) not finite (first: vertex " +
                                             std::to_string(first) + ")");
        ok = false;
    }
    for (const std::vector<Vec3>* values : {&mesh.polygon_reflectance, &mesh.polygon_emission})
        if (size_t first = firstBad(*values, bad); bad > 0) {
            diagnostics.error(mesh.location, what + ": " + std::to_string(bad) + " textured polygon colour(s) not finite (first: polygon " +
                                                 std::to_string(first) + ")");
            ok = false;
        }
    if (mesh.material >= material_count) {
        diagnostics.error(mesh.location, what + " refers to material " + std::to_string(mesh.material) + " of " +
                                             std::to_string(material_count));
        ok = false;
    }
    return ok;
}

// Per-vertex and per-polygon arrays that do not match their count cannot be trusted; they
// are optional data, so they are dropped rather than failing the scene.
void dropMismatchedArrays(Mesh& mesh, size_t index, Diagnostics& diagnostics) {
    const std::string what = describeMesh(mesh, index);
    auto drop = [&](std::vector<Vec3>& values, size_t expected, const char* kind) {
        if (values.empty() || values.size() == expected) return;
        diagnostics.warning(mesh.location, what + ": " + std::to_string(values.size()) + " " + kind + " for " +
                                               std::to_string(expected) + ", ignored");
        values.clear();
    };
    drop(mesh.vertex_colors, mesh.positions.size(), "vertex colours");
    drop(mesh.normals, mesh.positions.size(), "normals");
    drop(mesh.polygon_colors, mesh.polygon_count, "polygon colours");
    drop(mesh.polygon_reflectance, mesh.polygon_count, "textured polygon reflectances");
    drop(mesh.polygon_emission, mesh.polygon_count, "textured polygon emissions");
    if (!mesh.uv0.empty() && mesh.uv0.size() != mesh.positions.size()) {
        diagnostics.warning(mesh.location, what + ": " + std::to_string(mesh.uv0.size()) + " texture coordinates for " +
                                               std::to_string(mesh.positions.size()) + " vertices, ignored");
        mesh.uv0.clear();
    }
    if (!mesh.normals.empty() && std::any_of(mesh.normals.begin(), mesh.normals.end(),
                                             [](const Vec3& n) { return !isFinite(n); })) {
        diagnostics.warning(mesh.location, what + ": non-finite normals, ignored");
        mesh.normals.clear();
    }
    // A broken polygon map would corrupt every later stage: fall back to one polygon per triangle.
    bool map_ok = mesh.triangle_polygon.size() == mesh.triangles.size();
    for (size_t t = 0; map_ok && t < mesh.triangle_polygon.size(); ++t) {
        const uint32_t p = mesh.triangle_polygon[t];
        map_ok = p < mesh.polygon_count && (t == 0 ? true : (p == mesh.triangle_polygon[t - 1] ||
                                                             p == mesh.triangle_polygon[t - 1] + 1));
        if (t == 0) map_ok = map_ok && p == 0;
    }
    if (!map_ok) {
        if (!mesh.triangles.empty())
            diagnostics.warning(mesh.location, what + ": inconsistent triangle-to-polygon map, each triangle taken as a polygon");
        mesh.triangle_polygon.resize(mesh.triangles.size());
        for (size_t t = 0; t < mesh.triangles.size(); ++t) mesh.triangle_polygon[t] = static_cast<uint32_t>(t);
        mesh.polygon_count = static_cast<uint32_t>(mesh.triangles.size());
        mesh.polygon_colors.clear();
        mesh.polygon_reflectance.clear();
        mesh.polygon_emission.clear();
    }
}

struct CleanupCounts {
    size_t out_of_range = 0;
    size_t degenerate = 0;
    size_t unused_vertices = 0;
    size_t removed_polygons = 0;
};

bool isDegenerate(const Mesh& mesh, const UVec3& t, double min_height) {
    if (t.x == t.y || t.y == t.z || t.x == t.z) return true;
    const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    const double twice_area = glm::length(glm::cross(b - a, c - a));
    const double longest = std::sqrt(std::max({glm::length2(b - a), glm::length2(c - b), glm::length2(a - c)}));
    // Smallest height = 2 * area / longest edge.
    return !(twice_area > min_height * longest);
}

// Drops bad triangles, then polygons left without triangles, then unused vertices, keeping
// every parallel array in step and the polygon numbering contiguous.
CleanupCounts cleanMesh(Mesh& mesh, double min_height) {
    CleanupCounts counts;
    const size_t vertex_count = mesh.positions.size();
    std::vector<UVec3> triangles;
    std::vector<uint32_t> triangle_polygon;
    triangles.reserve(mesh.triangles.size());
    triangle_polygon.reserve(mesh.triangles.size());
    std::vector<uint32_t> new_polygon(mesh.polygon_count, UINT32_MAX);
    std::vector<uint32_t> kept_polygons;  // old ids in new order
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const UVec3& tri = mesh.triangles[t];
        if (tri.x >= vertex_count || tri.y >= vertex_count || tri.z >= vertex_count) {
            ++counts.out_of_range;
            continue;
        }
        if (isDegenerate(mesh, tri, min_height)) {
            ++counts.degenerate;
            continue;
        }
        const uint32_t old_polygon = mesh.triangle_polygon[t];
        if (new_polygon[old_polygon] == UINT32_MAX) {
            new_polygon[old_polygon] = static_cast<uint32_t>(kept_polygons.size());
            kept_polygons.push_back(old_polygon);
        }
        triangles.push_back(tri);
        triangle_polygon.push_back(new_polygon[old_polygon]);
    }
    counts.removed_polygons = mesh.polygon_count - kept_polygons.size();
    for (std::vector<Vec3>* per_polygon : {&mesh.polygon_colors, &mesh.polygon_reflectance, &mesh.polygon_emission}) {
        if (per_polygon->empty()) continue;
        std::vector<Vec3> kept;
        kept.reserve(kept_polygons.size());
        for (uint32_t old_polygon : kept_polygons) kept.push_back((*per_polygon)[old_polygon]);
        *per_polygon = std::move(kept);
    }
    mesh.polygon_count = static_cast<uint32_t>(kept_polygons.size());

    // Unused vertices: renumber the used ones in their original order.
    std::vector<uint32_t> new_vertex(vertex_count, UINT32_MAX);
    for (const UVec3& tri : triangles)
        for (int k = 0; k < 3; ++k) new_vertex[tri[k]] = 0;
    uint32_t next = 0;
    for (size_t v = 0; v < vertex_count; ++v)
        if (new_vertex[v] == 0) new_vertex[v] = next++;
    counts.unused_vertices = vertex_count - next;
    if (counts.unused_vertices > 0) {
        auto compact = [&](std::vector<Vec3>& values) {
            if (values.empty()) return;
            for (size_t v = 0; v < vertex_count; ++v)
                if (new_vertex[v] != UINT32_MAX) values[new_vertex[v]] = values[v];
            values.resize(next);
        };
        compact(mesh.positions);
        compact(mesh.normals);
        compact(mesh.vertex_colors);
        if (!mesh.uv0.empty()) {
            for (size_t v = 0; v < vertex_count; ++v)
                if (new_vertex[v] != UINT32_MAX) mesh.uv0[new_vertex[v]] = mesh.uv0[v];
            mesh.uv0.resize(next);
        }
        for (UVec3& tri : triangles) tri = UVec3(new_vertex[tri.x], new_vertex[tri.y], new_vertex[tri.z]);
    }
    mesh.triangles = std::move(triangles);
    mesh.triangle_polygon = std::move(triangle_polygon);
    return counts;
}

// Textured reflectance obeys the material rule (below 1, never negative): one warning per
// mesh naming the brightest value; emission is never negative.
void clampPolygonColors(Mesh& mesh, size_t index, Diagnostics& diagnostics) {
    size_t over = 0, negative = 0;
    Vec3 brightest(0.0f);
    for (Vec3& rho : mesh.polygon_reflectance) {
        if (glm::any(glm::greaterThanEqual(rho, Vec3(1.0f)))) {
            ++over;
            brightest = glm::max(brightest, rho);
        }
        if (glm::any(glm::lessThan(rho, Vec3(0.0f)))) ++negative;
        rho = glm::clamp(rho, Vec3(0.0f), Vec3(kMaxReflectance));
    }
    for (Vec3& emission : mesh.polygon_emission) emission = glm::max(emission, Vec3(0.0f));
    if (over > 0)
        diagnostics.warning(mesh.location, describeMesh(mesh, index) + ": textured reflectance up to " + vecText(brightest) +
                                               " >= 1 on " + std::to_string(over) + " polygon(s), clamped to " +
                                               std::to_string(kMaxReflectance));
    if (negative > 0)
        diagnostics.warning(mesh.location, describeMesh(mesh, index) + ": negative textured reflectance on " +
                                               std::to_string(negative) + " polygon(s), clamped to 0");
}

void reportCleanup(const Mesh& mesh, size_t index, const CleanupCounts& counts, Diagnostics& diagnostics) {
    std::string parts;
    auto add = [&](size_t count, const char* text) {
        if (count == 0) return;
        if (!parts.empty()) parts += ", ";
        parts += std::to_string(count) + " " + text;
    };
    add(counts.out_of_range, "triangle(s) with out-of-range indices");
    add(counts.degenerate, "degenerate triangle(s)");
    add(counts.unused_vertices, "unused vertex(es)");
    add(counts.removed_polygons, "polygon(s) left without triangles");
    if (!parts.empty()) diagnostics.warning(mesh.location, describeMesh(mesh, index) + ": dropped " + parts);
}

}  // namespace

bool validateScene(Scene& scene, Diagnostics& diagnostics, double max_memory_mb) {
    bool ok = true;
    std::vector<bool> factor_only(scene.materials.size(), false);
    for (const Mesh& mesh : scene.meshes)
        if (mesh.material < factor_only.size()) factor_only[mesh.material] = true;
    for (const Mesh& mesh : scene.meshes)
        if (mesh.material < factor_only.size() &&
            (mesh.polygon_count == 0 || mesh.polygon_reflectance.size() != mesh.polygon_count))
            factor_only[mesh.material] = false;
    for (size_t i = 0; i < scene.materials.size(); ++i)
        ok &= validateMaterial(scene.materials[i], i, factor_only[i], diagnostics);
    for (size_t i = 0; i < scene.lights.size(); ++i) ok &= validateLight(scene.lights[i], i, diagnostics);
    if (scene.sky.model != SkyModel::None && (!isFinite(scene.sky.radiance) || !isFinite(scene.sky.up))) {
        diagnostics.error({scene.source_path, 0, 0}, "the sky has a non-finite radiance or up axis");
        ok = false;
    }
    for (size_t i = 0; i < scene.cameras.size(); ++i) ok &= validateCamera(scene.cameras[i], i, diagnostics);
    for (size_t i = 0; i < scene.meshes.size(); ++i)
        ok &= checkMeshNumbers(scene.meshes[i], i, scene.materials.size(), diagnostics);
    if (!ok) return false;

    const double min_height = kDegenerateHeightSteps * kFloatStep * sceneExtent(scene.meshes);
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
        Mesh& mesh = scene.meshes[i];
        dropMismatchedArrays(mesh, i, diagnostics);
        clampPolygonColors(mesh, i, diagnostics);
        reportCleanup(mesh, i, cleanMesh(mesh, min_height), diagnostics);
    }
    const size_t before = scene.meshes.size();
    std::erase_if(scene.meshes, [](const Mesh& mesh) { return mesh.triangles.empty(); });
    if (const size_t removed = before - scene.meshes.size(); removed > 0)
        diagnostics.warning({scene.source_path, 0, 0}, std::to_string(removed) + " empty mesh(es) removed");
    if (scene.meshes.empty()) diagnostics.warning({scene.source_path, 0, 0}, "the scene has no surfaces");

    if (!validation::overlapCheckFits(scene, max_memory_mb, diagnostics)) return false;
    validation::reportCoplanarOverlaps(scene.meshes, diagnostics);
    return !diagnostics.hasErrors();
}

}  // namespace radbake
