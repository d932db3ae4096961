// Every scene format Assimp reads, mapped into our Scene. The only file in the project that
// includes Assimp, with ply_guard.cpp (which reads PLY with Assimp's own token functions):
// nothing of Assimp (types, exceptions, its global logger) leaks out of here.
#include "io/assimp/assimp_reader.h"

#include <assimp/BaseImporter.h>
#include <assimp/DefaultIOStream.h>
#include <assimp/DefaultIOSystem.h>
#include <assimp/DefaultLogger.hpp>
#include <assimp/GltfMaterial.h>
#include <assimp/Importer.hpp>
#include <assimp/Logger.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <string_view>

#include "core/regular_file.h"
#include "io/assimp/gltf_guard.h"
#include "io/assimp/obj_guard.h"
#include "io/assimp/ply_guard.h"
#include "scene/scene_budget.h"
#include "scene/triangulate.h"

namespace radbake {
namespace {


// ---------------------------------------------------------------------------------------
// Assimp's log -> Diagnostics. Assimp logs through one process-wide logger, so imports are
// serialised (kImportMutex) while ours is installed.

std::mutex kImportMutex;

// Assimp messages often name a line ("... line 12 ..."); lift it into the location so the
// user's editor can jump there, and keep the message whole.
SourceLocation locateMessage(const std::string& path, std::string_view message) {
    SourceLocation where{path, 0, 0};
    for (std::string_view key : {"line ", "Line ", "line:", "Line:"}) {
        size_t at = message.find(key);
        if (at == std::string_view::npos) continue;
        at += key.size();
        while (at < message.size() && message[at] == ' ') ++at;
        int line = 0;
        size_t digits = 0;
        while (at + digits < message.size() && digits < 9 && message[at + digits] >= '0' &&
               message[at + digits] <= '9')
            line = line * 10 + (message[at + digits++] - '0');
        if (digits > 0 && line > 0) {
            where.line = line;
            break;
        }
    }
    return where;
}

std::string trimMessage(const char* message) {
    std::string text = message ? message : "";
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
    return text;
}

class DiagnosticsLogger final : public Assimp::Logger {
public:
    DiagnosticsLogger(const std::string& path, Diagnostics& diagnostics)
        : Assimp::Logger(Assimp::Logger::NORMAL), path_(path), diagnostics_(diagnostics) {}

    bool attachStream(Assimp::LogStream*, unsigned int) override { return false; }
    bool detachStream(Assimp::LogStream*, unsigned int) override { return false; }

    // Logger errors during an import that still succeeds describe parts Assimp skipped:
    // warnings for us. A failed import is reported once, from the importer's error string.
    void OnWarn(const char* message) override { forward(message); }
    void OnError(const char* message) override { forward(message); }
    void OnInfo(const char*) override {}
    void OnDebug(const char*) override {}
    void OnVerboseDebug(const char*) override {}

    void finish() {
        if (suppressed_ > 0)
            diagnostics_.warning({path_, 0, 0}, "Assimp: " + std::to_string(suppressed_) + " more warnings (repeated or further) not shown");
    }

private:
    // A broken file can make Assimp warn once per line or per mesh; the first few distinct
    // messages say what is wrong, the rest are only counted.
    static constexpr size_t kMaxForwarded = 10;

    void forward(const char* message) {
        const std::string text = trimMessage(message);
        if (seen_.size() >= kMaxForwarded || !seen_.insert(text).second) {
            ++suppressed_;
            return;
        }
        diagnostics_.warning(locateMessage(path_, text), "Assimp: " + text);
    }

    std::string path_;
    Diagnostics& diagnostics_;
    std::set<std::string> seen_;
    int suppressed_ = 0;
};

// Installs the logger for one import and always removes it (DefaultLogger::set takes
// ownership and deletes the previous logger).
class ScopedLogger {
public:
    ScopedLogger(const std::string& path, Diagnostics& diagnostics)
        : logger_(new DiagnosticsLogger(path, diagnostics)) {
        Assimp::DefaultLogger::set(logger_);
    }
    ~ScopedLogger() {
        logger_->finish();
        Assimp::DefaultLogger::set(nullptr);
    }
    ScopedLogger(const ScopedLogger&) = delete;
    ScopedLogger& operator=(const ScopedLogger&) = delete;

private:
    DiagnosticsLogger* logger_;
};

// ---------------------------------------------------------------------------------------
// Conversions.

Vec3 toVec3(const aiVector3D& v) { return {v.x, v.y, v.z}; }
Vec3 toVec3(const aiColor3D& c) { return {c.r, c.g, c.b}; }

// aiMatrix4x4 is row-major for column vectors; glm is column-major for column vectors.
Mat4 toMat4(const aiMatrix4x4& m) {
    return Mat4(Vec4(m.a1, m.b1, m.c1, m.d1), Vec4(m.a2, m.b2, m.c2, m.d2), Vec4(m.a3, m.b3, m.c3, m.d3),
                Vec4(m.a4, m.b4, m.c4, m.d4));
}

Mat4 worldFromNode(const aiNode* node) {
    Mat4 world_from_node(1.0f);
    for (; node != nullptr; node = node->mParent) world_from_node = toMat4(node->mTransformation) * world_from_node;
    return world_from_node;
}

// Lights and cameras are placed by the node of the same name (Assimp's convention).
Mat4 worldFromNamed(const aiScene& ai, const aiString& name) {
    const aiNode* node = ai.mRootNode ? ai.mRootNode->FindNode(name) : nullptr;
    return node ? worldFromNode(node) : Mat4(1.0f);
}

std::string meshName(const aiNode& node, const aiMesh& mesh) {
    const std::string node_name = node.mName.C_Str();
    const std::string mesh_name = mesh.mName.C_Str();
    if (mesh_name.empty() || mesh_name == node_name) return node_name;
    if (node_name.empty()) return mesh_name;
    return node_name + "/" + mesh_name;
}

// The first texture of the first of `types` the material has, resolved against the model
// file's folder (MTL and glTF name textures relative to it), or the image file a glb or FBX
// embeds ("*0", or its file name), kept as bytes. Uncompressed embedded texels (rare) are not
// read: one warning, the material's colour is used.
TextureRef textureRef(const aiScene& ai, const aiMaterial& source, std::initializer_list<aiTextureType> types,
                      const std::string& path, Diagnostics& diagnostics) {
    for (const aiTextureType type : types) {
        aiString texture;
        if (source.GetTexture(type, 0, &texture) != AI_SUCCESS || texture.length == 0) continue;
        std::string name = texture.C_Str();
        if (const aiTexture* embedded = ai.GetEmbeddedTexture(name.c_str())) {
            if (embedded->mHeight != 0 || embedded->pcData == nullptr) {
                diagnostics.warning({path, 0, 0}, "embedded texture '" + name +
                                                      "' holds raw texels, which are not read; the material's own colour is used");
                return {};
            }
            const char* bytes = reinterpret_cast<const char*>(embedded->pcData);
            return {.path = path + "#" + name,
                    .location = {path, 0, 0},
                    .embedded = std::make_shared<const std::string>(bytes, bytes + embedded->mWidth)};
        }
        std::replace(name.begin(), name.end(), '\\', '/');  // MTL files written on Windows
        const std::filesystem::path file(name);
        const std::filesystem::path resolved = file.is_absolute() ? file : std::filesystem::path(path).parent_path() / file;
        return {.path = resolved.lexically_normal().string(), .location = {path, 0, 0}};
    }
    return {};
}

Material convertMaterial(const aiScene& ai, const aiMaterial& source, const std::string& path, Diagnostics& diagnostics) {
    Material material;
    material.location = {path, 0, 0};
    aiString name;
    if (source.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) material.name = name.C_Str();
    aiColor3D color;
    if (source.Get(AI_MATKEY_COLOR_DIFFUSE, color) == AI_SUCCESS) material.reflectance = toVec3(color);
    if (source.Get(AI_MATKEY_COLOR_EMISSIVE, color) == AI_SUCCESS) material.emission = toVec3(color);
    // Light through the surface (Material::transparency): MTL d / Tr and glTF's BLEND alpha as
    // opacity, KHR_materials_transmission's factor. glTF OPAQUE ignores the alpha; MASK cuts the
    // surface out where the alpha is low, which a material-wide value cannot: baked opaque, warned.
    float opacity = 1.0f;
    aiString alpha_mode;
    const bool gltf_alpha = source.Get(AI_MATKEY_GLTF_ALPHAMODE, alpha_mode) == AI_SUCCESS;
    const std::string mode = gltf_alpha ? alpha_mode.C_Str() : "";
    if (source.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && (!gltf_alpha || mode == "BLEND"))
        material.transparency = 1.0f - opacity;
    float transmission = 0.0f;
    if (source.Get(AI_MATKEY_TRANSMISSION_FACTOR, transmission) == AI_SUCCESS)
        material.transparency = std::max(material.transparency, transmission);
    if (mode == "MASK")
        diagnostics.warning(material.location, "material '" + material.name +
                                                   "': alphaMode MASK (cut-out) is not modelled; baked opaque");
    material.base_color_texture = textureRef(ai, source, {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}, path, diagnostics);
    material.emissive_texture = textureRef(ai, source, {aiTextureType_EMISSIVE}, path, diagnostics);
    material.normal_texture = textureRef(ai, source, {aiTextureType_NORMALS}, path, diagnostics);
    return material;
}

// The smaller full view angle. Assimp 5.2.5's importers store the FULL horizontal angle in
// mHorizontalFOV whatever its comment says (assimp issues #2256, #5691), and glTF's stores
// yfov * aspect (issue #4435), which we undo exactly.
float smallerFieldOfView(const aiCamera& camera, bool gltf, float fallback) {
    const float aspect = camera.mAspect;
    const float horizontal = camera.mHorizontalFOV;
    float vertical = horizontal;
    if (aspect > 0.0f)
        vertical = gltf ? horizontal / aspect : 2.0f * std::atan(std::tan(0.5f * horizontal) / aspect);
    const float fov = std::min(horizontal, vertical);
    return fov > 0.0f && fov < static_cast<float>(kPi) ? fov : fallback;
}

bool isGltf(const std::string& path) {
    std::string extension = path.size() >= 5 ? path.substr(path.size() - 5) : path;
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return extension == ".gltf" || extension.ends_with(".glb");
}

struct PrimitiveCounts {
    size_t points = 0;
    size_t lines = 0;
};

// One aiMesh instance under one node -> one world-space Mesh, keeping source polygons.
Mesh convertMesh(const aiMesh& source, const aiNode& node, const Mat4& world_from_object, uint32_t material_offset,
                 const std::string& path, PrimitiveCounts& dropped) {
    Mesh mesh;
    mesh.name = meshName(node, source);
    mesh.location = {path, 0, 0};
    mesh.material = material_offset + source.mMaterialIndex;

    mesh.positions.reserve(source.mNumVertices);
    for (unsigned v = 0; v < source.mNumVertices; ++v)
        mesh.positions.push_back(Vec3(world_from_object * Vec4(toVec3(source.mVertices[v]), 1.0f)));
    if (source.HasNormals()) {
        const Mat3 normal_from_object = glm::transpose(glm::inverse(Mat3(world_from_object)));
        mesh.normals.reserve(source.mNumVertices);
        for (unsigned v = 0; v < source.mNumVertices; ++v) {
            const Vec3 n = normal_from_object * toVec3(source.mNormals[v]);
            const float length = glm::length(n);
            mesh.normals.push_back(length > 0.0f ? n / length : n);
        }
    }
    if (source.HasTextureCoords(0)) {
        mesh.uv0.reserve(source.mNumVertices);
        for (unsigned v = 0; v < source.mNumVertices; ++v)
            mesh.uv0.emplace_back(source.mTextureCoords[0][v].x, source.mTextureCoords[0][v].y);
    }
    if (source.HasVertexColors(0)) {
        mesh.vertex_colors.reserve(source.mNumVertices);
        for (unsigned v = 0; v < source.mNumVertices; ++v) {
            const aiColor4D& c = source.mColors[0][v];
            mesh.vertex_colors.push_back({c.r, c.g, c.b});
        }
    }

    // A mirroring transform turns counter-clockwise loops clockwise; reverse them so the
    // front stays where the file put it.
    const bool mirrored = glm::determinant(Mat3(world_from_object)) < 0.0f;
    std::vector<uint32_t> loop;
    for (unsigned f = 0; f < source.mNumFaces; ++f) {
        const aiFace& face = source.mFaces[f];
        if (face.mNumIndices == 1) {
            ++dropped.points;
            continue;
        }
        if (face.mNumIndices == 2) {
            ++dropped.lines;
            continue;
        }
        if (face.mNumIndices < 3) continue;
        loop.assign(face.mIndices, face.mIndices + face.mNumIndices);
        if (mirrored) std::reverse(loop.begin(), loop.end());
        const size_t before = mesh.triangles.size();
        // Out-of-range indices and non-finite positions are for validation to drop or report;
        // the triangulator must not see them, so such a polygon is fanned instead. So is a
        // polygon with no area at all, so that validation counts its triangles as degenerate.
        bool clean = true;
        for (uint32_t index : loop) clean = clean && index < mesh.positions.size() && isFinite(mesh.positions[index]);
        if (clean && loop.size() > 3)
            triangulatePolygon(mesh.positions, std::span<const uint32_t>(loop), false, mesh.triangles);
        if (mesh.triangles.size() == before)
            for (size_t i = 1; i + 1 < loop.size(); ++i) mesh.triangles.push_back({loop[0], loop[i], loop[i + 1]});
        mesh.triangle_polygon.resize(mesh.triangles.size(), mesh.polygon_count);
        ++mesh.polygon_count;
    }
    return mesh;
}

struct Converter {
    const aiScene& ai;
    const std::string& path;
    Scene& scene;
    Diagnostics& diagnostics;
    uint32_t material_offset = 0;
    PrimitiveCounts dropped{};

    void visit(const aiNode& node, const Mat4& world_from_parent) {
        const Mat4 world_from_node = world_from_parent * toMat4(node.mTransformation);
        for (unsigned i = 0; i < node.mNumMeshes; ++i) {
            const unsigned index = node.mMeshes[i];
            if (index >= ai.mNumMeshes || ai.mMeshes[index] == nullptr) continue;
            const aiMesh& source = *ai.mMeshes[index];
            Mesh mesh = convertMesh(source, node, world_from_node, material_offset, path, dropped);
            mesh.solid = isSingleSided(source.mMaterialIndex);
            if (!mesh.triangles.empty()) scene.meshes.push_back(std::move(mesh));
        }
        for (unsigned c = 0; c < node.mNumChildren; ++c)
            if (node.mChildren[c]) visit(*node.mChildren[c], world_from_node);
    }

    // Two-sided (lit on both sides, scene/two_sided.h) only where the file says so: a material
    // with AI_MATKEY_TWOSIDED set (glTF `doubleSided`, which Assimp's glTF importer copies
    // there; FBX, COLLADA and 3DS flags). OBJ, PLY and most others promise nothing: one-sided,
    // as the front of every face is lit.
    bool isSingleSided(unsigned material) const {
        if (material >= ai.mNumMaterials || ai.mMaterials[material] == nullptr) return true;
        int two_sided = 0;
        if (ai.mMaterials[material]->Get(AI_MATKEY_TWOSIDED, two_sided) == AI_SUCCESS) return two_sided == 0;
        return true;
    }

    void convertMaterials() {
        material_offset = static_cast<uint32_t>(scene.materials.size());
        for (unsigned m = 0; m < ai.mNumMaterials; ++m)
            scene.materials.push_back(ai.mMaterials[m] ? convertMaterial(ai, *ai.mMaterials[m], path, diagnostics) : Material{});
        // A mesh must always have a material to point at.
        if (ai.mNumMaterials == 0) {
            Material fallback;
            fallback.name = "default";
            fallback.location = {path, 0, 0};
            scene.materials.push_back(fallback);
        }
    }

    void convertLights() {
        size_t skipped = 0;
        for (unsigned l = 0; l < ai.mNumLights; ++l) {
            const aiLight* source = ai.mLights[l];
            if (!source) continue;
            Light light;
            light.name = source->mName.C_Str();
            switch (source->mType) {
                case aiLightSource_POINT: light.type = LightType::Point; break;
                case aiLightSource_SPOT: light.type = LightType::Spot; break;
                case aiLightSource_DIRECTIONAL: light.type = LightType::Directional; break;
                default: ++skipped; continue;  // ambient and area lights have no punctual meaning
            }
            const Mat4 world_from_light = worldFromNamed(ai, source->mName);
            light.position = Vec3(world_from_light * Vec4(toVec3(source->mPosition), 1.0f));
            const Vec3 direction = Mat3(world_from_light) * toVec3(source->mDirection);
            const float length = glm::length(direction);
            light.direction = length > 0.0f ? direction / length : Vec3(0.0f, 0.0f, -1.0f);
            // Assimp folds intensity into the colour; split it back so colour stays in [0, 1].
            const Vec3 color = toVec3(source->mColorDiffuse);
            const float intensity = std::max(color.x, std::max(color.y, color.z));
            light.intensity = intensity;
            light.color = intensity > 0.0f ? color / intensity : Vec3(1.0f);
            light.attenuation = {source->mAttenuationConstant, source->mAttenuationLinear,
                                 source->mAttenuationQuadratic};
            // Assimp gives lights no range: they reach everywhere.
            light.radius = std::numeric_limits<float>::infinity();
            if (light.type == LightType::Spot) {
                // Taken as half-angles from the axis, as glTF (and VRML) define them.
                light.beam_width = source->mAngleInnerCone;
                light.cut_off_angle = source->mAngleOuterCone;
            }
            light.location = {path, 0, 0};
            scene.lights.push_back(light);
        }
        if (skipped > 0)
            diagnostics.warning({path, 0, 0}, std::to_string(skipped) + " ambient/area light(s) ignored");
    }

    void convertCameras() {
        const bool gltf = isGltf(path);
        for (unsigned c = 0; c < ai.mNumCameras; ++c) {
            const aiCamera* source = ai.mCameras[c];
            if (!source) continue;
            const Mat4 world_from_camera = worldFromNamed(ai, source->mName);
            Camera camera;
            camera.name = source->mName.C_Str();
            camera.location = {path, 0, 0};
            // Assimp 5.2.5's glTF importer copies the node's translation into mPosition as
            // well, so the node transform would apply it twice; glTF cameras sit at their node.
            const Vec3 p_camera = gltf ? Vec3(0.0f) : toVec3(source->mPosition);
            camera.position = Vec3(world_from_camera * Vec4(p_camera, 1.0f));
            const Vec3 look = Mat3(world_from_camera) * toVec3(source->mLookAt);
            const Vec3 up = Mat3(world_from_camera) * toVec3(source->mUp);
            const Vec3 right = glm::cross(look, up);
            if (glm::length(right) > 0.0f && glm::length(look) > 0.0f) {
                const Vec3 z = -glm::normalize(look);
                const Vec3 x = glm::normalize(right);
                camera.orientation = glm::quat_cast(Mat3(x, glm::cross(z, x), z));
            }
            camera.field_of_view = smallerFieldOfView(*source, gltf, camera.field_of_view);
            scene.cameras.push_back(camera);
        }
    }

    void run() {
        convertMaterials();
        if (ai.mRootNode) visit(*ai.mRootNode, Mat4(1.0f));
        if (dropped.points > 0)
            diagnostics.warning({path, 0, 0}, std::to_string(dropped.points) + " point primitive(s) ignored");
        if (dropped.lines > 0)
            diagnostics.warning({path, 0, 0}, std::to_string(dropped.lines) + " line primitive(s) ignored");
        convertLights();
        convertCameras();
    }
};

// Only regular files can be read. A name in the file (an OBJ's `mtllib`, a texture) may be a
// folder, which fopen opens on Linux: Assimp 5.2.5's OBJ importer then throws on the failed
// read and leaks the stream (found by tools/fuzz/fuzz_assimp_obj); a FIFO or /dev/stdin would
// block the import. Such a name is treated as a missing file.
bool isRegularFile(const char* file) {
    std::error_code ec;
    return file != nullptr && std::filesystem::is_regular_file(file, ec);
}

// Assimp's stream over a file opened here (its constructor from a FILE* is protected).
class RegularFileStream final : public Assimp::DefaultIOStream {
public:
    RegularFileStream(std::FILE* file, const std::string& name) : Assimp::DefaultIOStream(file, name) {}
};

// Assimp's own file access under the read policy, noting every file it opens (the scene, its
// MTL, ...) and every one it asks for and does not find. It reads; a file is opened only when
// the policy allows it and it is regular, checked on the open file itself.
class RecordingIOSystem final : public Assimp::DefaultIOSystem {
public:
    RecordingIOSystem(const std::string& model, const AssimpReads& reads, Diagnostics& diagnostics)
        : model_(model), reads_(reads), diagnostics_(diagnostics) {}
    bool Exists(const char* file) const override { return isRegularFile(file) && allowed(file); }
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (file == nullptr || mode == nullptr || std::string_view(mode).find_first_of("wa+") != std::string_view::npos)
            return nullptr;
        if (!allowed(file)) return nullptr;
        std::string why;
        InputFile opened = openRegularFile(file, why, reads_.policy->max_bytes, reads_.policy->openedCheck());
        if (!opened) {
            // In the read roots, missing or not: adding it, or replacing what is there, rebuilds.
            note(reads_.files_read, file);
            std::error_code ec;
            if (std::filesystem::exists(file, ec)) {
                note(reads_.files_refused, file);  // not a regular file, or too large
                warnOnce(file, why);
            }
            return nullptr;
        }
        note(reads_.files_read, file);
        return new RegularFileStream(opened.release(), file);
    }

private:
    // The model file itself always (it may be a link to elsewhere); anything else as the
    // policy says, warned once per path.
    bool allowed(const char* file) const {
        if (model_ == file) return true;
        const std::string why = reads_.policy->whyOutside(file);
        if (why.empty()) return true;
        note(reads_.files_refused, file);
        warnOnce(file, why);
        return false;
    }
    void warnOnce(const std::string& file, const std::string& why) const {
        if (std::find(warned_.begin(), warned_.end(), file) != warned_.end()) return;
        warned_.push_back(file);
        diagnostics_.warning({model_, 0, 0}, "'" + file + "' not read: " + why + "; read as missing");
    }
    static void note(std::vector<std::string>* list, const std::string& file) {
        if (list) list->push_back(file);
    }

    std::string model_;
    AssimpReads reads_;
    Diagnostics& diagnostics_;
    mutable std::vector<std::string> warned_;
};

// ---------------------------------------------------------------------------------------
// Checks before Assimp sees a file, for inputs that crash Assimp 5.2.5 (docs/fuzzing.md).

// True when `path` ends in "." + one of the importer's extensions (any case), as Assimp
// compares them (whole endings: "mesh.xml" too).
bool claims(Assimp::BaseImporter& candidate, const std::string& path) {
    std::set<std::string> extensions;
    candidate.GetExtensionList(extensions);
    std::string lower = path;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    return std::any_of(extensions.begin(), extensions.end(), [&](const std::string& extension) {
        return lower.size() > extension.size() && lower[lower.size() - extension.size() - 1] == '.' &&
               lower.compare(lower.size() - extension.size(), extension.size(), extension) == 0;
    });
}

// Importers never used, whatever the file: Assimp 5.2.5's OpenGEX parser reads past its
// buffer on a 20-byte file (fuzz_assimp_gltf, docs/fuzzing.md).
struct LeftOutFormat {
    const char* extension;
    const char* name;
};
constexpr LeftOutFormat kLeftOutFormats[] = {{"ogex", "OpenGEX"}};

const LeftOutFormat* leftOutFormat(Assimp::BaseImporter& candidate) {
    std::set<std::string> extensions;
    candidate.GetExtensionList(extensions);
    for (const LeftOutFormat& format : kLeftOutFormats)
        if (extensions.count(format.extension)) return &format;
    return nullptr;
}

// ".obj" for "Mesh.OBJ".
std::string lowerExtension(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
    return extension;
}

// A file named as a left-out format is a located error, before Assimp sees it.
bool checkLeftOutFormat(const std::string& path, Diagnostics& diagnostics) {
    const std::string extension = lowerExtension(path);
    for (const LeftOutFormat& format : kLeftOutFormats) {
        if (extension != std::string(".") + format.extension) continue;
        diagnostics.error({path, 0, 0}, std::string(format.name) +
                                            " files are not read: Assimp 5.2.5's reader runs past its buffer on malformed ones");
        return false;
    }
    return true;
}

// When the importers of a file's extension all refuse it, Assimp guesses the format from the
// content with every other importer: a damaged .gltf went to the OpenGEX reader, which
// overflows its buffer (fuzz_assimp_gltf). A file whose extension some importer claims is read
// by those importers only (the others leave `importer` and are owned by `removed`); a file
// with an unknown extension is still recognised by its content, never as a left-out format.
// Returns whether some importer claims the extension.
bool keepClaimingImporters(Assimp::Importer& importer, const std::string& path,
                           std::vector<std::unique_ptr<Assimp::BaseImporter>>& removed) {
    std::vector<Assimp::BaseImporter*> others, left_out;
    bool claimed = false;
    for (size_t i = 0; i < importer.GetImporterCount(); ++i) {
        Assimp::BaseImporter* candidate = importer.GetImporter(i);
        if (!candidate) continue;
        if (leftOutFormat(*candidate)) left_out.push_back(candidate);
        else if (claims(*candidate, path)) claimed = true;
        else others.push_back(candidate);
    }
    if (claimed) left_out.insert(left_out.end(), others.begin(), others.end());
    for (Assimp::BaseImporter* other : left_out)
        if (importer.UnregisterLoader(other) == aiReturn_SUCCESS) removed.emplace_back(other);
    return claimed;
}



// Reading a file with Assimp peaks at about this many bytes per byte of the file: its parse,
// the aiScene and JoinIdenticalVertices' copies at once (dense binary meshes the most).
constexpr double kAssimpPeakPerFileByte = 16.0;

// The read asked of the budget before Assimp starts it.
bool fitsAssimpRead(const std::string& path, MemoryGauge& memory, Diagnostics& diagnostics) {
    std::error_code ec;
    const double size = static_cast<double>(std::filesystem::file_size(path, ec));
    const double need = kAssimpPeakPerFileByte * size;
    if (ec || memory.fits(need)) return true;
    diagnostics.error({path, 0, 0}, "reading this " + bytesText(size) + " file with Assimp takes about " + bytesText(need) +
                                        ", more than the memory budget leaves (" +
                                        bytesText(std::max(memory.roomBytes(), 0.0)) + " of " +
                                        bytesText(memory.budgetMegabytes() * 1048576.0) + "; --max-memory)");
    return false;
}

// The scene Assimp read, asked of the budget before it is converted.
bool fitsConversion(const std::string& path, const aiScene& ai, MemoryGauge& memory, Diagnostics& diagnostics) {
    double triangles = 0.0, bytes = 0.0;
    for (unsigned m = 0; m < ai.mNumMeshes; ++m) {
        const aiMesh& mesh = *ai.mMeshes[m];
        double mesh_triangles = 0.0;
        for (unsigned f = 0; f < mesh.mNumFaces; ++f)
            mesh_triangles += std::max(0.0, double(mesh.mFaces[f].mNumIndices) - 2.0);
        triangles += mesh_triangles;
        bytes += meshBytesEstimate(double(mesh.mNumVertices), mesh_triangles);
    }
    if (memory.fits(bytes)) return true;
    diagnostics.error({path, 0, 0}, overBudgetMessage("the file", double(ai.mNumMeshes), triangles, bytes, memory));
    return false;
}

bool importLocked(const std::string& path, Scene& scene, Diagnostics& diagnostics, const AssimpReads& reads) {
    if (!checkLeftOutFormat(path, diagnostics) || !checkPlyInput(path, reads.policy->max_bytes, diagnostics) ||
        !checkGltfInput(path, reads.policy->max_bytes, diagnostics))
        return false;
    ScopedLogger logger(path, diagnostics);
    std::vector<std::unique_ptr<Assimp::BaseImporter>> removed;  // outlives the importer's use of them
    Assimp::Importer importer;
    const bool claimed = keepClaimingImporters(importer, path, removed);
    // The OBJ importer reads .obj files and may recognise one of an unclaimed extension.
    if ((!claimed || lowerExtension(path) == ".obj") && !checkObjInput(path, reads.policy->max_bytes, diagnostics))
        return false;
    importer.SetIOHandler(new RecordingIOSystem(path, reads, diagnostics));  // the importer owns it
    // Bone-only files would otherwise gain made-up skeleton meshes.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
    // No Triangulate and no GenNormals: they would hide source polygons and input problems.
    // No FindInvalidData either: it silently deletes a mesh with a NaN position, which
    // validation must report as a located error instead (it also drops bad normals itself).
    const unsigned flags = aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure;
    if (reads.memory && !fitsAssimpRead(path, *reads.memory, diagnostics)) return false;
    const aiScene* ai = importer.ReadFile(path, flags);
    if (ai == nullptr) {
        std::string message = trimMessage(importer.GetErrorString());
        if (message.empty()) message = "unknown error";
        diagnostics.error(locateMessage(path, message), "cannot read scene with Assimp: " + message);
        return false;
    }
    if (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE) diagnostics.warning({path, 0, 0}, "Assimp: the scene is incomplete");
    if (reads.memory && !fitsConversion(path, *ai, *reads.memory, diagnostics)) return false;
    Converter converter{.ai = *ai, .path = path, .scene = scene, .diagnostics = diagnostics};
    converter.run();
    return true;
}

}  // namespace

bool readWithAssimp(const std::string& path, Scene& scene, Diagnostics& diagnostics, const AssimpReads& given) {
    // The module boundary: neither Assimp's exceptions nor ours (bad_alloc) get out.
    try {
        AssimpReads reads = given;
        ReadPolicy model_folder;
        if (!reads.policy) {
            model_folder = readPolicyFor(path, {});
            reads.policy = &model_folder;
        }
        std::lock_guard<std::mutex> lock(kImportMutex);
        return importLocked(path, scene, diagnostics, reads);
    } catch (const std::exception& e) {
        diagnostics.error({path, 0, 0}, std::string("cannot read scene with Assimp: ") + e.what());
    } catch (...) {
        diagnostics.error({path, 0, 0}, "cannot read scene with Assimp: unknown exception");
    }
    return false;
}

}  // namespace radbake
