#include "export/ply_writer.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

#include "export/gltf_writer.h"
#include "export/mesh_attributes.h"
#include "export/output_transaction.h"

namespace radbake {

static_assert(std::endian::native == std::endian::little, "the PLY writer copies host numbers as little-endian");

namespace {
template <typename T>
void appendRaw(std::string& out, const T& value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
}

// Comments may not hold line breaks.
std::string oneLine(std::string text) {
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    return text;
}
}  // namespace

namespace {

// One mesh as the PLY writes it: the scene mesh itself, or its lightmap mesh (split at chart
// seams) with the lightmap UV and atlas per vertex.
struct PlyMesh {
    std::vector<Vec3> positions, normals, values;
    std::vector<Vec2> uv;        // lightmap runs only
    std::vector<uint8_t> atlas;  // lightmap runs only; kNoLightmap where the mesh has no charts
    const std::vector<UVec3>* triangles = nullptr;
};

constexpr uint8_t kNoLightmap = 255;

PlyMesh plyMesh(const Mesh& mesh, const std::vector<Vec3>& values, const LightmapMesh* lightmap_mesh,
                bool with_lightmaps, size_t& non_finite) {
    PlyMesh out;
    if (lightmap_mesh && !lightmap_mesh->triangles.empty()) {
        out.positions = lightmap_mesh->positions;
        out.normals = lightmapVertexNormals(mesh, *lightmap_mesh);
        out.values = lightmapVertexValues(mesh, *lightmap_mesh, &values, non_finite);
        out.uv = lightmap_mesh->uv;
        for (const int atlas : lightmap_mesh->atlas) out.atlas.push_back(static_cast<uint8_t>(atlas));
        out.triangles = &lightmap_mesh->triangles;
        return out;
    }
    out.positions = mesh.positions;
    out.normals = vertexNormals(mesh);
    out.values = finiteVertexValues(mesh, &values, non_finite);
    if (with_lightmaps) {
        out.uv.assign(mesh.positions.size(), Vec2(0.0f));
        out.atlas.assign(mesh.positions.size(), kNoLightmap);
    }
    out.triangles = &mesh.triangles;
    return out;
}

}  // namespace

std::string encodePly(const Scene& scene, const VertexBake& bake, const PlyOptions& options,
                      Diagnostics& diagnostics) {
    if (!checkBakeMatchesScene(scene, bake, diagnostics)) return {};
    const LightmapFiles* lightmaps = options.lightmaps;
    if (lightmaps && !checkLightmapsMatchScene(scene, *lightmaps, diagnostics)) return {};
    if (lightmaps && lightmaps->atlas_files.size() >= kNoLightmap) {
        diagnostics.error({}, "too many lightmap atlases for the PLY's uchar lightmap index (" +
                                  std::to_string(lightmaps->atlas_files.size()) + ", at most 254)");
        return {};
    }
    size_t non_finite = 0;
    std::vector<PlyMesh> meshes;
    size_t vertex_count = 0, face_count = 0;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        meshes.push_back(plyMesh(scene.meshes[m], bake.values[m], lightmaps ? &lightmaps->meshes[m] : nullptr,
                                 lightmaps != nullptr, non_finite));
        vertex_count += meshes.back().positions.size();
        face_count += meshes.back().triangles->size();
    }
    if (vertex_count > static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
        diagnostics.error({}, "scene too large for PLY int vertex indices");
        return {};
    }

    std::string out = "ply\nformat binary_little_endian 1.0\n";
    out += "comment generator " + oneLine(options.generator) + "\n";
    out += "comment scene " + oneLine(scene.name) + "\n";
    out += "comment red green blue: baked irradiance H/pi per vertex, linear float, unclamped\n";
    if (lightmaps) {
        out += "comment u1 v1: lightmap UV (u right, v down from the image's top row) in the atlas named by lightmap\n";
        out += "comment lightmap: atlas index, 255 where the mesh has no lightmap\n";
        for (size_t k = 0; k < lightmaps->atlas_files.size(); ++k)
            out += "comment lightmap " + std::to_string(k) + " " + oneLine(lightmaps->atlas_files[k]) + "\n";
    }
    out += "element vertex " + std::to_string(vertex_count) + "\n";
    for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"})
        out += std::string("property float ") + name + "\n";
    if (lightmaps) out += "property float u1\nproperty float v1\nproperty uchar lightmap\n";
    out += "element face " + std::to_string(face_count) + "\n";
    out += "property list uchar int vertex_indices\nend_header\n";

    out.reserve(out.size() + vertex_count * (lightmaps ? 45 : 36) + face_count * 13);
    for (const PlyMesh& mesh : meshes) {
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            appendRaw(out, mesh.positions[v]);
            appendRaw(out, mesh.normals[v]);
            appendRaw(out, mesh.values[v]);
            if (!lightmaps) continue;
            appendRaw(out, mesh.uv[v]);
            appendRaw(out, mesh.atlas[v]);
        }
    }
    int32_t base = 0;
    for (const PlyMesh& mesh : meshes) {
        for (const UVec3& t : *mesh.triangles) {
            appendRaw(out, uint8_t{3});
            appendRaw(out, base + static_cast<int32_t>(t.x));
            appendRaw(out, base + static_cast<int32_t>(t.y));
            appendRaw(out, base + static_cast<int32_t>(t.z));
        }
        base += static_cast<int32_t>(mesh.positions.size());
    }
    if (non_finite > 0)
        diagnostics.warning({}, std::to_string(non_finite) + " baked vertex values were not finite and were written as 0");
    return out;
}

bool writePly(const std::filesystem::path& path, const Scene& scene, const VertexBake& bake,
              const PlyOptions& options, Diagnostics& diagnostics) {
    const std::string bytes = encodePly(scene, bake, options, diagnostics);
    if (bytes.empty()) return false;
    return writeFileBytes(path, bytes, diagnostics);
}

}  // namespace radbake
