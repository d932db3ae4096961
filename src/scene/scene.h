#pragma once
// The one in-memory scene every reader produces and every later stage reads.
// Everything is in world space, in metres (after --unit-scale), with radiometric
// quantities as DESIGN.md section 2 defines them.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "scene/environment_map.h"

namespace radbake {

// A texture file a material names: the path as resolved against the file that named it, and
// where it was named (for the warning when it cannot be read). Empty path: no texture.
struct TextureRef {
    std::string path;
    SourceLocation location;
    // The image file's bytes when the model file holds them (glb, FBX): `path` then only names
    // it in messages ("scene.glb#*0") and is no file of its own.
    std::shared_ptr<const std::string> embedded;
    // VRML97: an RGB(A) texture replaces the colour, an intensity (1- or 2-channel) one
    // modulates it. Otherwise (MTL, glTF, VRML 1.0 Texture2) texture times colour.
    bool rgb_replaces = false;

    bool empty() const { return path.empty(); }
};

struct Material {
    std::string name;
    // Diffuse rho per channel, in [0, 1); where a texture gives every polygon of the
    // material's meshes its own (Mesh::polygon_reflectance), only the factor, kept as given.
    Vec3 reflectance{0.8f};
    Vec3 emission{0.0f};     // emitted radiance L_e, W sr^-1 m^-2 (times --emission-scale)
    float ambient_intensity = 0.2f;
    // The share of light that passes through the surface unchanged in direction (a thin pane,
    // no refraction); the rest meets it as an opaque surface of this reflectance would
    // (meshTransmittance: clamped to [0, 1]).
    float transparency = 0.0f;
    TextureRef base_color_texture;  // sets the reflectance per polygon (scene/textures.h)
    TextureRef emissive_texture;    // sets the emission per polygon
    TextureRef normal_texture;      // passed through to the glb, not used by the solve
    SourceLocation location;

    bool isEmitter() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

// "No mesh" for Mesh::twin.
inline constexpr uint32_t kNoMesh = 0xffffffffu;

// A triangle mesh with one material. Triangles remember the source polygon they came from
// (convex source polygons are the natural radiosity patches): triangle_polygon[t] is the
// index of t's polygon, polygons are numbered 0..polygon_count-1 and a polygon's triangles
// are contiguous.
struct Mesh {
    std::string name;
    std::vector<Vec3> positions;         // world space
    std::vector<Vec3> normals;           // per vertex, world space; empty when not given
    std::vector<Vec3> vertex_colors;     // per vertex; empty when not given
    std::vector<Vec3> polygon_colors;    // per polygon; empty when not given
    std::vector<Vec2> uv0;               // per vertex, the source's first UV set (v up, as OBJ and VRML); empty when none
    // Per polygon, where a texture sets them (applyTextures): they replace the material's
    // reflectance and emission for that polygon. Empty: the material's.
    std::vector<Vec3> polygon_reflectance;
    std::vector<Vec3> polygon_emission;
    std::vector<UVec3> triangles;        // counter-clockwise seen from the front
    std::vector<uint32_t> triangle_polygon;
    uint32_t polygon_count = 0;
    uint32_t material = 0;               // index into Scene::materials
    // Mixed lighting (--realtime-lights): the name under which the engine draws this emissive
    // mesh's own light; the read-out then leaves that light's direct part out. Empty: baked.
    std::string realtime_light;
    // False: two-sided, lit on both sides, each with its own light (VRML `solid FALSE`, a
    // VRML 1.0 face set not SOLID with a known ordering, a material marked double-sided).
    bool solid = true;
    // Two-sided meshes (scene/two_sided.h): the other side's mesh, kNoMesh when none; `back`
    // marks the back twin (reversed winding, negated normals), which follows every original mesh.
    uint32_t twin = kNoMesh;
    bool back = false;
    // Two-sided in the source, but closed with nothing lit inside (settleClosedTwoSided): its
    // backs face only its own dark volume, so it is baked one-sided (solid true), exactly.
    bool closed_two_sided = false;
    // Radians: an edge whose faces meet at a larger angle is hard, and the vertices along it
    // are split (scene/creases.h); smaller angles are smooth.
    float crease_angle = 0.0f;
    bool convex_solid = false;           // the reader knows this is one closed convex solid (Box, Cylinder, ...)
    SourceLocation location;             // the node that made it
};

enum class LightType { Point, Spot, Directional };

struct Light {
    std::string name;      // the source's (a VRML97 DEF name, an Assimp node name, "sun"); may be empty
    LightType type = LightType::Point;
    Vec3 position{0.0f};   // world; unused for Directional
    Vec3 direction{0.0f, 0.0f, -1.0f};  // world, unit; unused for Point
    Vec3 color{1.0f};
    float intensity = 1.0f;
    float ambient_intensity = 0.0f;
    Vec3 attenuation{1.0f, 0.0f, 0.0f};  // constant, linear, quadratic
    float radius = 100.0f;               // world units; infinite for Directional
    float beam_width = 1.570796f;        // radians (Spot)
    float cut_off_angle = 0.785398f;     // radians (Spot)
    bool on = true;
    // Directional only: the angle (radians) the source subtends, a disc (the sun: 0.53 degrees),
    // which gives shadows penumbrae; 0, a point at infinity (VRML's DirectionalLight).
    float angular_diameter = 0.0f;
    // The meshes the light reaches, sorted, when `scoped`: a VRML97 DirectionalLight lights
    // only its siblings and their descendants (ISO/IEC 14772-1, DirectionalLight), a VRML 1.0
    // light what follows it in its Separator. Not scoped: every mesh (VRML97 PointLight and
    // SpotLight are global, so are Assimp's lights).
    bool scoped = false;
    std::vector<uint32_t> scope;
    // Mixed lighting (--realtime-lights): the engine draws this light's direct light, so the
    // solve bounces it but the read-out leaves its direct light out of every point.
    bool realtime = false;
    SourceLocation location;

    bool lights(uint32_t mesh) const;
};

// Light from every direction, at infinity (scene/daylight.h: its radiance by direction). The
// uniform and overcast skies are black below the horizon (the plane through each receiver normal
// to `up`); a Background and an environment map (scene/environment_map.h) cover the whole sphere.
enum class SkyModel { None, Uniform, Overcast, Background, Map };

// A VRML97 Background's sky and ground (ISO/IEC 14772-1, 6.5): sky_color[0] at the zenith,
// sky_color[i] at sky_angle[i - 1] (radians from the zenith), linear between, the last colour
// beyond; the ground likewise from the nadir, drawn over the sky within its last angle.
struct BackgroundSky {
    std::vector<float> sky_angle, ground_angle;
    std::vector<Vec3> sky_color{Vec3(0.0f)}, ground_color;
    SourceLocation location;
};

struct Sky {
    SkyModel model = SkyModel::None;
    BackgroundSky background;  // SkyModel::Background: its colours, times `radiance`
    std::shared_ptr<const EnvironmentMap> map;  // SkyModel::Map: its radiances, times `radiance`
    // W sr^-1 m^-2 per channel: the uniform sky's radiance, the overcast sky's at the zenith.
    Vec3 radiance{1.0f};
    Vec3 up{0.0f, 1.0f, 0.0f};  // unit, world

    bool shines() const {
        return model != SkyModel::None && (model != SkyModel::Map || map) && (radiance.x > 0.0f || radiance.y > 0.0f || radiance.z > 0.0f);
    }
};

struct Camera {
    std::string name;
    Vec3 position{0.0f, 0.0f, 10.0f};
    Quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  // rotates the default view (looking down -Z, +Y up)
    float field_of_view = 0.785398f;           // radians, the smaller of the two view angles
    SourceLocation location;
};

// What splitHardEdges did at import (scene/creases.h).
struct CreaseSplitCounts {
    size_t meshes = 0;    // meshes with a hard edge through a shared vertex
    size_t vertices = 0;  // vertices that were shared across a hard edge
    size_t added = 0;     // vertices added by splitting them
};

struct Scene {
    std::string name;         // file stem, used for output names
    std::string source_path;  // as given
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Light> lights;
    Sky sky;  // none from a file: set by the import's daylight options (scene/daylight.h)
    // The file's first VRML97 Background, which --sky background lights the scene with.
    std::optional<BackgroundSky> background;
    std::vector<Camera> cameras;
    // Every file the import read, the scene file first, each once (Inline'd and EXTERNPROTO
    // files, MTL files, ...): what a depfile names and what provenance hashes.
    // A file the import looked for and did not find is an input too: adding it rebuilds.
    std::vector<std::string> input_files;
    // Files the scene named and the read policy refused (core/read_policy.h), each once, as
    // named: outside the read roots, or not a regular file. None of them was read.
    std::vector<std::string> refused_inputs;
    // The import's read roots beyond the scene's folder (--read-root), set by the import: a
    // later stage that reads a texture again (the glb writer) checks the file it opens against
    // the same policy. Unset for a scene made without an import: no policy then.
    std::optional<std::vector<std::string>> read_roots;
    CreaseSplitCounts crease_split;
    // Back twins' polygons covered by a surface in contact (scene/two_sided.h).
    size_t covered_back_polygons = 0;
};

// Summary figures used by `radbake info` and by later stages.
struct SceneSummary {
    // Back twins (scene/two_sided.h) are not counted: a two-sided surface counts once here
    // and once in two_sided_meshes.
    size_t triangles = 0;
    size_t polygons = 0;
    size_t vertices = 0;
    double area = 0.0;  // total one-sided area
    size_t two_sided_meshes = 0;    // meshes lit on both sides
    size_t two_sided_polygons = 0;  // their polygons
    size_t two_sided_closed_meshes = 0;  // two-sided in the source, closed and dark inside: one-sided
    Vec3 bounds_min{0.0f};
    Vec3 bounds_max{0.0f};
    size_t materials = 0;
    size_t emitters = 0;  // emissive polygons
    size_t lights = 0;
};

double triangleArea(const Mesh& mesh, size_t triangle);

// The reflectance and emission the solve uses for one polygon of a mesh: the per-polygon
// value when a texture set one, else the material's (zero without a material).
Vec3 polygonReflectance(const Scene& scene, const Mesh& mesh, uint32_t polygon);
Vec3 polygonEmission(const Scene& scene, const Mesh& mesh, uint32_t polygon);
SceneSummary summarize(const Scene& scene);

// The share of light a mesh's surfaces let through (Material::transparency in [0, 1]; 0 without
// a material): a ray crossing it keeps that share, and the surface reflects rho times the rest.
float meshTransmittance(const Scene& scene, const Mesh& mesh);

}  // namespace radbake
