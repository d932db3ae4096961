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

std::string encodePly(const Scene& scene, const VertexBake& bake, const PlyOptions& options,
                      Diagnostics& diagnostics) {
    if (!checkBakeMatchesScene(scene, bake, diagnostics)) return {};
    size_t vertex_count = 0, face_count = 0;
    for (const Mesh& mesh : scene.meshes) {
        vertex_count += mesh.positions.size();
        face_count += mesh.triangles.size();
    }
    if (vertex_count > static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
        diagnostics.error({}, "scene too large for PLY int vertex indices");
        return {};
    }

    std::string out = "ply\nformat binary_little_endian 1.0\n";
    out += "comment generator " + oneLine(options.generator) + "\n";
    out += "comment scene " + oneLine(scene.name) + "\n";
    out += "comment red green blue: baked irradiance H/pi per vertex, linear float, unclamped\n";
    out += "element vertex " + std::to_string(vertex_count) + "\n";
    for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"})
        out += std::string("property float ") + name + "\n";
    out += "element face " + std::to_string(face_count) + "\n";
    out += "property list uchar int vertex_indices\nend_header\n";

    out.reserve(out.size() + vertex_count * 36 + face_count * 13);
    size_t non_finite = 0;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        const std::vector<Vec3> normals = vertexNormals(mesh);
        const std::vector<Vec3> values = finiteVertexValues(mesh, &bake.values[m], non_finite);
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            appendRaw(out, mesh.positions[v]);
            appendRaw(out, normals[v]);
            appendRaw(out, values[v]);
        }
    }
    int32_t base = 0;
    for (const Mesh& mesh : scene.meshes) {
        for (const UVec3& t : mesh.triangles) {
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
