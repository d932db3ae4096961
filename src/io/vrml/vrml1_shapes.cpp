// VRML 1.0 reader: shapes (IndexedFaceSet and primitives) split by material binding, lights,
// cameras and WWWInline.
#include <algorithm>
#include <map>
#include <unordered_map>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numeric>
#include <optional>
#include <span>

#include "io/vrml/primitives.h"
#include "io/vrml/vrml1_parser.h"
#include "io/vrml/vrml_transform.h"
#include "scene/triangulate.h"

namespace radbake::vrml {
namespace {

// VRML 1.0 lights have no range: they reach everywhere.
constexpr float kUnboundedRadius = std::numeric_limits<float>::infinity();

const Vrml1MaterialList& defaultMaterial() {
    static const Vrml1MaterialList list = [] {
        Vrml1MaterialList m;
        m.name = "default";
        return m;
    }();
    return list;
}

template <typename T>
const T& pick(const std::vector<T>& values, uint32_t index) {
    return index < values.size() ? values[index] : values.front();
}


// True when the face, seen along its Newell normal, turns the same way at every corner. Files
// often keep the default faceType CONVEX for faces that are not; those are ear-clipped.
bool looksConvex(const std::vector<Vec3>& positions, std::span<const uint32_t> loop) {
    const size_t n = loop.size();
    if (n <= 3) return true;
    DVec3 normal(0.0);
    for (size_t i = 0; i < n; ++i) {
        const DVec3 a(positions[loop[i]]), b(positions[loop[(i + 1) % n]]);
        normal += DVec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    for (size_t i = 0; i < n; ++i) {
        const DVec3 a(positions[loop[i]]), b(positions[loop[(i + 1) % n]]), c(positions[loop[(i + 2) % n]]);
        if (glm::dot(glm::cross(b - a, c - b), normal) < 0.0) return false;
    }
    return true;
}

}  // namespace

uint32_t Vrml1Parser::sceneMaterial(const Vrml1State& state, uint32_t index) {
    const Vrml1MaterialList& list = state.material ? *state.material : defaultMaterial();
    const auto key = std::make_tuple(list.key, index, state.texture);
    const auto found = materials_.find(key);
    if (found != materials_.end()) return found->second;

    Material material;
    material.name = list.count() > 1 ? list.name + "[" + std::to_string(index) + "]" : list.name;
    material.reflectance = pick(list.diffuse, index);
    material.emission = pick(list.emissive, index);
    material.transparency = pick(list.transparency, index);
    // VRML97 keeps ambient light as a fraction of the diffuse colour.
    const Vec3 ambient = pick(list.ambient, index);
    const float diffuse_sum = material.reflectance.x + material.reflectance.y + material.reflectance.z;
    if (diffuse_sum > 0.0f)
        material.ambient_intensity = std::clamp((ambient.x + ambient.y + ambient.z) / diffuse_sum, 0.0f, 1.0f);
    // Texture2 times the diffuse colour (Open Inventor's default MODULATE; VRML 1.0 says no more).
    if (!state.texture.empty())
        if (const std::optional<std::string> resolved = resolveUrl(path_, state.texture))
            material.base_color_texture = {.path = *resolved, .location = state.texture_location};
    material.location = list.location.file.empty() ? SourceLocation{path_, 0, 0} : list.location;
    scene_.materials.push_back(std::move(material));
    const uint32_t id = static_cast<uint32_t>(scene_.materials.size() - 1);
    materials_.emplace(key, id);
    return id;
}

void Vrml1Parser::emitShape(const Vrml1Shape& shape, const Vrml1State& state, const std::string& name,
                            const SourceLocation& where) {
    const std::vector<Vec3>& positions = *shape.positions;
    // Asked of the budget before it is built: USE re-reads can repeat a shape many times.
    const double bytes = meshBytesEstimate(double(positions.size()), double(shape.triangles.size()));
    if (options_.memory && !options_.memory->reserve(bytes)) {
        if (!failed_)
            diagnostics_.error(where, "the scene's meshes outgrow the memory budget at this " + name + " (" +
                                          std::to_string(scene_.meshes.size()) + " meshes so far; --max-memory " +
                                          bytesText(options_.memory->budgetMegabytes() * 1048576.0) + ")");
        failed_ = true;
        return;
    }
    // Triangles grouped by material, keeping file order inside a group (so each polygon's
    // triangles stay together): one mesh per material.
    std::vector<uint32_t> order(shape.triangles.size());
    std::iota(order.begin(), order.end(), 0u);
    auto material_of = [&](uint32_t t) { return shape.polygon_material[shape.triangle_polygon[t]]; };
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return material_of(a) < material_of(b); });

    const bool mirrored = glm::determinant(glm::dmat3(state.world_from_object)) < 0.0;
    const bool flip = mirrored != shape.clockwise;
    std::vector<uint32_t> remap(positions.size(), UINT32_MAX);
    std::vector<uint32_t> touched;
    // With texture coordinates a vertex is a (coordinate, texture coordinate) pair.
    const bool has_uv = !shape.triangle_uv.empty() && state.tex_coords;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> uv_vertex;
    for (size_t begin = 0; begin < order.size();) {
        const uint32_t material_index = material_of(order[begin]);
        size_t end = begin;
        while (end < order.size() && material_of(order[end]) == material_index) ++end;

        Mesh mesh;
        mesh.name = name;
        mesh.location = where;
        mesh.solid = shape.solid;
        mesh.crease_angle = shape.crease_angle;
        mesh.material = sceneMaterial(state, material_index);
        uint32_t last_polygon = UINT32_MAX;
        for (size_t i = begin; i < end; ++i) {
            const uint32_t t = order[i];
            UVec3 tri = shape.triangles[t];
            for (int k = 0; k < 3; ++k) {
                if (has_uv) {
                    const uint32_t uv = shape.triangle_uv[t][k];
                    const auto [it, added] = uv_vertex.try_emplace({tri[k], uv}, static_cast<uint32_t>(mesh.positions.size()));
                    if (added) {
                        mesh.positions.push_back(transformPoint(state.world_from_object, positions[tri[k]]));
                        mesh.uv0.push_back((*state.tex_coords)[uv]);
                    }
                    tri[k] = it->second;
                    continue;
                }
                uint32_t& slot = remap[tri[k]];
                if (slot == UINT32_MAX) {
                    slot = static_cast<uint32_t>(mesh.positions.size());
                    mesh.positions.push_back(transformPoint(state.world_from_object, positions[tri[k]]));
                    touched.push_back(tri[k]);
                }
                tri[k] = slot;
            }
            if (flip) std::swap(tri.y, tri.z);
            mesh.triangles.push_back(tri);
            if (shape.triangle_polygon[t] != last_polygon) {
                last_polygon = shape.triangle_polygon[t];
                ++mesh.polygon_count;
            }
            mesh.triangle_polygon.push_back(mesh.polygon_count - 1);
        }
        for (uint32_t v : touched) remap[v] = UINT32_MAX;
        touched.clear();
        uv_vertex.clear();
        mesh.convex_solid = shape.convex_solid && begin == 0 && end == order.size();
        scene_.meshes.push_back(std::move(mesh));
        begin = end;
    }
}

bool Vrml1Parser::parseIndexedFaceSet(const Token& type, const std::string& def_name, Vrml1State& state,
                                      int depth) {
    std::vector<int32_t> coord_index, material_index, tex_index, ignored;
    const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
        if (f.text == "coordIndex") return readInts(f, coord_index) ? 1 : -1;
        if (f.text == "materialIndex") return readInts(f, material_index) ? 1 : -1;
        if (f.text == "textureCoordIndex") return readInts(f, tex_index) ? 1 : -1;
        if (f.text == "normalIndex") return readInts(f, ignored) ? 1 : -1;
        return 0;
    });
    if (!ok || !emit_) return ok;

    static const std::vector<Vec3> no_coords;
    const std::vector<Vec3>& coords = state.coords ? *state.coords : no_coords;
    // The default materialIndex [-1] means "not given".
    const bool has_material_index = !(material_index.empty() || (material_index.size() == 1 && material_index[0] == -1));
    const uint32_t material_count = static_cast<uint32_t>(state.material ? state.material->count() : 1);

    Vrml1Shape shape;
    shape.positions = &coords;
    shape.solid = state.solid_shape && state.ordering_known;
    shape.clockwise = state.clockwise;
    shape.crease_angle = state.crease_angle;

    // Texture coordinates per corner: textureCoordIndex, or coordIndex when it is the default
    // [-1]; kept only when every used corner has one.
    const size_t tex_count = state.tex_coords ? state.tex_coords->size() : 0;
    const bool tex_default = tex_index.empty() || (tex_index.size() == 1 && tex_index[0] == -1);
    const std::vector<int32_t>& corner_tex = tex_default ? coord_index : tex_index;
    bool use_uv = tex_count > 0 && corner_tex.size() >= coord_index.size();
    for (size_t k = 0; use_uv && k < coord_index.size(); ++k)
        use_uv = coord_index[k] < 0 || (corner_tex[k] >= 0 && static_cast<size_t>(corner_tex[k]) < tex_count);
    if (tex_count > 0 && !use_uv) warn(type, "texture coordinates do not match the faces; ignored");
    std::unordered_map<uint32_t, uint32_t> loop_uv;  // coordinate -> texture coordinate in the current face

    if (state.material_binding == Vrml1Binding::PerVertex || state.material_binding == Vrml1Binding::PerVertexIndexed)
        warnOnce("per-vertex-material", type, "per-vertex materials reduced to one per face (the first corner's)");
    size_t dropped = 0, bad_material = 0;
    int32_t face = 0;     // ordinal of the face among all faces in coordIndex
    int32_t corner = 0;   // ordinal of the face's first corner (PER_VERTEX)
    std::vector<uint32_t> loop;
    for (size_t start = 0; start < coord_index.size();) {
        size_t end = start;
        while (end < coord_index.size() && coord_index[end] >= 0) ++end;
        // coord_index[end] is -1 (face end), another negative index, or the end of the list.
        bool bad = end < coord_index.size() && coord_index[end] != -1;
        size_t stop = end;
        if (bad)
            while (stop < coord_index.size() && coord_index[stop] != -1) ++stop;
        if (stop > start) {
            loop.clear();
            for (size_t i = start; i < end; ++i) {
                const int32_t v = coord_index[i];
                if (static_cast<size_t>(v) >= coords.size()) bad = true;
                else loop.push_back(static_cast<uint32_t>(v));
            }
            int32_t m = 0;
            switch (state.material_binding) {
                case Vrml1Binding::Overall: break;
                case Vrml1Binding::PerPart:
                case Vrml1Binding::PerFace: m = face; break;
                case Vrml1Binding::PerPartIndexed:
                case Vrml1Binding::PerFaceIndexed:
                    m = has_material_index ? (static_cast<size_t>(face) < material_index.size() ? material_index[face] : -1)
                                           : face;
                    break;
                case Vrml1Binding::PerVertex: m = corner; break;
                case Vrml1Binding::PerVertexIndexed:
                    // A mesh has one material: a face takes its first corner's.
                    m = has_material_index ? (start < material_index.size() ? material_index[start] : -1)
                                           : coord_index[start];
                    break;
            }
            if (m < 0 || static_cast<uint32_t>(m) >= material_count) {
                ++bad_material;
                m = 0;
            }
            if (bad || loop.size() < 3) {
                ++dropped;
            } else {
                const bool convex = state.convex_faces && looksConvex(coords, loop);
                const size_t made = triangulatePolygon(coords, loop, convex, shape.triangles);
                if (made > 0 && use_uv) {
                    loop_uv.clear();
                    for (size_t i = start; i < end; ++i)
                        loop_uv.try_emplace(static_cast<uint32_t>(coord_index[i]), static_cast<uint32_t>(corner_tex[i]));
                    for (size_t t = shape.triangles.size() - made; t < shape.triangles.size(); ++t) {
                        const UVec3& tri = shape.triangles[t];
                        shape.triangle_uv.emplace_back(loop_uv[tri.x], loop_uv[tri.y], loop_uv[tri.z]);
                    }
                }
                if (made > 0) {
                    shape.triangle_polygon.insert(shape.triangle_polygon.end(), made,
                                                  static_cast<uint32_t>(shape.polygon_material.size()));
                    shape.polygon_material.push_back(static_cast<uint32_t>(m));
                } else {
                    ++dropped;
                }
            }
            ++face;
            corner += static_cast<int32_t>(end - start);
        }
        start = stop + 1;
    }
    const std::string name = !def_name.empty()           ? def_name
                             : !state.group_name.empty() ? state.group_name
                                                         : "IndexedFaceSet";
    if (dropped > 0)
        warn(type, name + ": " + std::to_string(dropped) +
                       " face(s) with fewer than 3 corners or coordinate indices out of range (" +
                       std::to_string(coords.size()) + " points) dropped");
    if (bad_material > 0)
        warn(type, name + ": " + std::to_string(bad_material) + " face(s) with a material index out of range (" +
                       std::to_string(material_count) + " materials) use material 0");
    if (!shape.triangles.empty()) emitShape(shape, state, name, loc(type));
    return true;
}

bool Vrml1Parser::parsePrimitive(Vrml1Kind kind, const Token& type, const std::string& def_name,
                                 Vrml1State& state, int depth) {
    float width = 2.0f, height = 2.0f, depth_size = 2.0f, radius = 1.0f;
    std::vector<std::string> parts{"ALL"};
    const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
        bool read = false;
        switch (kind) {
            case Vrml1Kind::Cube:
                if (f.text == "width") read = readFloat(f, width);
                else if (f.text == "height") read = readFloat(f, height);
                else if (f.text == "depth") read = readFloat(f, depth_size);
                else return 0;
                break;
            case Vrml1Kind::Sphere:
                if (f.text == "radius") read = readFloat(f, radius);
                else return 0;
                break;
            default:  // Cylinder, Cone
                if (f.text == "parts") read = readBitMask(f, parts);
                else if (f.text == "height") read = readFloat(f, height);
                else if (f.text == (kind == Vrml1Kind::Cone ? "bottomRadius" : "radius")) read = readFloat(f, radius);
                else return 0;
                break;
        }
        return read ? 1 : -1;
    });
    if (!ok || !emit_) return ok;

    auto has = [&](const char* part) {
        return std::find(parts.begin(), parts.end(), "ALL") != parts.end() ||
               std::find(parts.begin(), parts.end(), part) != parts.end();
    };
    Mesh object;
    // Part of each appended polygon, for PER_PART / PER_FACE bindings.
    std::vector<uint32_t> polygon_part;
    auto addPart = [&](uint32_t part) {
        polygon_part.resize(object.polygon_count, part);
    };
    switch (kind) {
        case Vrml1Kind::Cube:
            appendBox(object, Vec3(width, height, depth_size));
            // appendBox makes +X -X +Y -Y +Z -Z; VRML 1.0 numbers the faces front (+Z), back,
            // left (-X), right, top (+Y), bottom.
            polygon_part = {3, 2, 4, 5, 0, 1};
            break;
        case Vrml1Kind::Sphere:
            appendSphere(object, radius);
            addPart(0);
            break;
        case Vrml1Kind::Cylinder:
            if (has("SIDES")) {
                appendCylinder(object, radius, height, true, false, false);
                addPart(0);
            }
            if (has("TOP")) {
                appendCylinder(object, radius, height, false, true, false);
                addPart(1);
            }
            if (has("BOTTOM")) {
                appendCylinder(object, radius, height, false, false, true);
                addPart(2);
            }
            object.convex_solid = has("SIDES") && has("TOP") && has("BOTTOM") && radius > 0 && height > 0;
            break;
        default:  // Cone
            if (has("SIDES")) {
                appendCone(object, radius, height, true, false);
                addPart(0);
            }
            if (has("BOTTOM")) {
                appendCone(object, radius, height, false, true);
                addPart(1);
            }
            object.convex_solid = has("SIDES") && has("BOTTOM") && radius > 0 && height > 0;
            break;
    }
    if (object.triangles.empty()) return true;

    const bool per_part = state.material_binding == Vrml1Binding::PerPart ||
                          state.material_binding == Vrml1Binding::PerPartIndexed ||
                          state.material_binding == Vrml1Binding::PerFace ||
                          state.material_binding == Vrml1Binding::PerFaceIndexed;
    const uint32_t material_count = static_cast<uint32_t>(state.material ? state.material->count() : 1);
    Vrml1Shape shape;
    shape.positions = &object.positions;
    shape.triangles = std::move(object.triangles);
    shape.triangle_polygon = std::move(object.triangle_polygon);
    shape.polygon_material.resize(object.polygon_count, 0);
    if (per_part)
        for (uint32_t p = 0; p < object.polygon_count; ++p)
            shape.polygon_material[p] = polygon_part[p] < material_count ? polygon_part[p] : 0;
    shape.convex_solid = object.convex_solid;
    shape.solid = true;
    shape.crease_angle = object.crease_angle;
    const std::string name = !def_name.empty()           ? def_name
                             : !state.group_name.empty() ? state.group_name
                                                         : std::string(type.text);
    emitShape(shape, state, name, loc(type));
    return true;
}

bool Vrml1Parser::parseLight(Vrml1Kind kind, const Token& type, Vrml1State& state, int depth) {
    Light light;
    Vec3 location(0.0f, 0.0f, 1.0f), direction(0.0f, 0.0f, -1.0f);
    float drop_off_rate = 0.0f;
    const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
        bool read = false;
        if (f.text == "on") read = readBool(f, light.on);
        else if (f.text == "intensity") read = readFloat(f, light.intensity);
        else if (f.text == "color") read = readVec3(f, light.color);
        else if (f.text == "location" && kind != Vrml1Kind::DirectionalLight) read = readVec3(f, location);
        else if (f.text == "direction" && kind != Vrml1Kind::PointLight) read = readVec3(f, direction);
        else if (f.text == "dropOffRate" && kind == Vrml1Kind::SpotLight) read = readFloat(f, drop_off_rate);
        else if (f.text == "cutOffAngle" && kind == Vrml1Kind::SpotLight) read = readFloat(f, light.cut_off_angle);
        else return 0;
        return read ? 1 : -1;
    });
    if (!ok || !emit_) return ok;
    light.type = kind == Vrml1Kind::PointLight  ? LightType::Point
                 : kind == Vrml1Kind::SpotLight ? LightType::Spot
                                                : LightType::Directional;
    light.location = loc(type);
    light.radius = kUnboundedRadius;
    if (light.type != LightType::Directional) light.position = transformPoint(state.world_from_object, location);
    if (light.type != LightType::Point)
        light.direction = transformDirection(state.world_from_object, direction, Vec3(0.0f, 0.0f, -1.0f));
    if (light.type == LightType::Spot) {
        // Inventor's fall-off is cos^(128 dropOffRate); VRML97-style lights have full intensity
        // inside beam_width, so take the angle where that fall-off halves the intensity.
        light.beam_width = light.cut_off_angle;
        if (drop_off_rate > 0.0f) {
            const double half = std::acos(std::pow(0.5, 1.0 / (128.0 * drop_off_rate)));
            light.beam_width = std::min(light.cut_off_angle, static_cast<float>(half));
        }
    }
    if (!light_frames_.empty()) light_frames_.back().emplace_back(scene_.lights.size(), scene_.meshes.size());
    scene_.lights.push_back(light);
    return true;
}

bool Vrml1Parser::parseCamera(const Token& type, const std::string& def_name, Vrml1State& state, int depth) {
    Camera camera;
    Vec3 position(0.0f, 0.0f, 1.0f);
    DVec3 axis(0, 0, 1);
    double angle = 0.0;
    float height_angle = 0.785398f;
    const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
        bool read = false;
        if (f.text == "position") read = readVec3(f, position);
        else if (f.text == "orientation") read = readRotation(f, axis, angle);
        else if (f.text == "heightAngle") read = readFloat(f, height_angle);
        else if (f.text == "focalDistance") read = skipValue(f);
        else return 0;
        return read ? 1 : -1;
    });
    if (!ok || !emit_) return ok;
    camera.name = def_name.empty() ? "PerspectiveCamera" : def_name;
    camera.position = transformPoint(state.world_from_object, position);
    const double length = glm::length(axis);
    const Quat local = length > 0.0 && std::isfinite(angle)
                           ? Quat(glm::angleAxis(angle, axis / length))
                           : Quat(1, 0, 0, 0);
    camera.orientation = glm::normalize(rotationOf(state.world_from_object) * local);
    camera.field_of_view = height_angle;
    camera.location = loc(type);
    scene_.cameras.push_back(camera);
    return true;
}

bool Vrml1Parser::parseInline(const Token& type, Vrml1State& state, int depth) {
    std::string url;
    const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
        if (f.text == "name") return readString(f, url) ? 1 : -1;
        if (f.text == "bboxSize" || f.text == "bboxCenter") return skipValue(f) ? 1 : -1;
        return 0;
    });
    if (!ok || !emit_) return ok;
    if (url.empty()) {
        warn(type, "WWWInline without a name ignored");
        return true;
    }
    const std::optional<std::string> resolved = resolveUrl(path_, url);
    if (!resolved) {
        warn(type, "WWWInline '" + url + "' is not a local file; skipped");
        return true;
    }
    // As the VRML97 reader does: a missing file is skipped with a warning (an error with
    // --strict), and the recursion guard compares canonical paths.
    if (!mayRead(*resolved, loc(type), "WWWInline", options_, diagnostics_)) return true;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(*resolved, ec)) {
        noteMissing(*resolved, options_);
        const std::string message = "WWWInline file '" + *resolved + "' not found; skipped";
        if (options_.strict) diagnostics_.error(loc(type), message);
        else warn(type, message);
        return true;
    }
    const std::string key = std::filesystem::weakly_canonical(*resolved, ec).string();
    if (std::find(inline_stack_.begin(), inline_stack_.end(), key) != inline_stack_.end()) {
        warn(type, "WWWInline '" + url + "' includes itself (a file already being read); skipped");
        return true;
    }
    const std::optional<std::string> text = loadText(*resolved, loc(type), options_, diagnostics_);
    if (!text) return true;  // loadText reported where and why

    const size_t meshes = scene_.meshes.size(), lights = scene_.lights.size(), cameras = scene_.cameras.size();
    inline_stack_.push_back(key);
    readText(*text, *resolved, options_, inline_stack_, scene_, diagnostics_);
    inline_stack_.pop_back();

    // What the inline appended is in its own coordinates: place it here.
    transformAppended(scene_, meshes, lights, cameras, state.world_from_object);
    return true;
}

}  // namespace radbake::vrml
