#include "io/vrml/vrml97_builder.h"
#include "io/vrml/vrml_transform.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "io/vrml/primitives.h"
#include "io/vrml/vrml97_parser.h"

namespace radbake::vrml {
namespace {

const std::vector<float> kNoFloats;
const std::vector<int32_t> kNoInts;
const std::vector<std::string> kNoStrings;


}  // namespace

bool readVrml97(std::string_view text, const std::string& path, const VrmlOptions& options,
                std::vector<std::string>& inline_stack, Scene& scene, Diagnostics& diagnostics) {
    std::vector<NodePtr> roots;
    Vrml97Parser parser(text, path, options, inline_stack, diagnostics);
    if (!parser.parse(roots)) return false;
    Vrml97Builder builder(path, options, inline_stack, scene, diagnostics);
    return builder.build(roots);
}

Vrml97Builder::Vrml97Builder(std::string path, const VrmlOptions& options, std::vector<std::string>& inline_stack,
                             Scene& scene, Diagnostics& diagnostics)
    : path_(std::move(path)), options_(options), inline_stack_(inline_stack), scene_(scene),
      diagnostics_(diagnostics) {}

bool Vrml97Builder::build(const std::vector<NodePtr>& roots) {
    const int errors_before = diagnostics_.errorCount();
    for (const Mesh& mesh : scene_.meshes) triangles_ += mesh.triangles.size();
    if (!expansionFits(roots)) return false;
    openLightScope();  // the file is a group of its top-level nodes (an Inline's children)
    for (const NodePtr& root : roots) visit(root, DMat4(1.0), 0);
    closeLightScope();
    return !aborted_ && diagnostics_.errorCount() == errors_before;
}

void Vrml97Builder::abort(const SourceLocation& where, const std::string& message) {
    if (!aborted_) diagnostics_.error(where, message);
    aborted_ = true;
}

void Vrml97Builder::warnOnce(const std::string& key, const SourceLocation& where, const std::string& message) {
    if (warned_.emplace(key, true).second) diagnostics_.warning(where, message);
}

// ---- field access -------------------------------------------------------------------------

float Vrml97Builder::sfFloat(const Node& node, std::string_view name, float fallback) const {
    const FieldValue* f = node.field(name);
    return f && !f->floats.empty() ? f->floats[0] : fallback;
}
bool Vrml97Builder::sfBool(const Node& node, std::string_view name, bool fallback) const {
    const FieldValue* f = node.field(name);
    return f && !f->ints.empty() ? f->ints[0] != 0 : fallback;
}
int32_t Vrml97Builder::sfInt(const Node& node, std::string_view name, int32_t fallback) const {
    const FieldValue* f = node.field(name);
    return f && !f->ints.empty() ? f->ints[0] : fallback;
}
Vec3 Vrml97Builder::sfVec3(const Node& node, std::string_view name, Vec3 fallback) const {
    const FieldValue* f = node.field(name);
    return f && f->floats.size() >= 3 ? Vec3(f->floats[0], f->floats[1], f->floats[2]) : fallback;
}
Vec4 Vrml97Builder::sfRotation(const Node& node, std::string_view name, Vec4 fallback) const {
    const FieldValue* f = node.field(name);
    return f && f->floats.size() >= 4 ? Vec4(f->floats[0], f->floats[1], f->floats[2], f->floats[3]) : fallback;
}
const std::vector<float>& Vrml97Builder::mfFloats(const Node& node, std::string_view name) const {
    const FieldValue* f = node.field(name);
    return f ? f->floats : kNoFloats;
}
const std::vector<int32_t>& Vrml97Builder::mfInts(const Node& node, std::string_view name) const {
    const FieldValue* f = node.field(name);
    return f ? f->ints : kNoInts;
}
const std::vector<std::string>& Vrml97Builder::mfStrings(const Node& node, std::string_view name) const {
    const FieldValue* f = node.field(name);
    return f ? f->strings : kNoStrings;
}
NodePtr Vrml97Builder::sfNode(const Node& node, std::string_view name) {
    const FieldValue* f = node.field(name);
    return f && !f->nodes.empty() ? resolve(f->nodes[0]) : nullptr;
}

// ---- PROTO expansion ------------------------------------------------------------------------

NodePtr Vrml97Builder::resolve(const NodePtr& start) {
    NodePtr node = start;
    int depth = 0;
    while (node && node->proto && !aborted_) {
        if (node->proto->unresolved) return nullptr;  // the parser warned at the EXTERNPROTO
        if (++depth > vrml97Limits().max_proto_depth) {
            abort(node->location, "PROTO instances nested deeper than " +
                                      std::to_string(vrml97Limits().max_proto_depth) + " levels");
            return nullptr;
        }
        if (!node->expansion) node->expansion = expand(*node);
        node = node->expansion;
    }
    return aborted_ ? nullptr : node;
}

NodePtr Vrml97Builder::expand(const Node& instance) {
    const ProtoDef& proto = *instance.proto;
    if (proto.body.empty()) return nullptr;
    std::unordered_map<std::string, const FieldValue*> env;
    for (const InterfaceField& f : proto.interface) {
        if (f.is_event) continue;
        const FieldValue* given = instance.field(f.name);
        env[f.name] = given ? given : &f.default_value;
    }
    std::unordered_map<const Node*, NodePtr> memo;
    return copyTemplate(proto.body.front(), env, memo);
}

NodePtr Vrml97Builder::copyTemplate(const NodePtr& node, const std::unordered_map<std::string, const FieldValue*>& env,
                                    std::unordered_map<const Node*, NodePtr>& memo) {
    // Nodes with no IS below them are the same in every instance: share them.
    if (!node || !node->subtree_has_is || aborted_) return node;
    if (const auto it = memo.find(node.get()); it != memo.end()) return it->second;
    if (++expanded_nodes_ > vrml97Limits().max_expanded_nodes) {
        abort(node->location, "PROTO expansion makes more than " + std::to_string(vrml97Limits().max_expanded_nodes) +
                                  " nodes");
        return nullptr;
    }
    auto copy = std::make_shared<Node>();
    copy->type = node->type;
    copy->name = node->name;
    copy->location = node->location;
    copy->proto = node->proto;
    copy->fields.reserve(node->fields.size());
    for (const Field& f : node->fields) {
        copy->fields.push_back({f.name, {}});
        FieldValue& value = copy->fields.back().value;
        value.type = f.value.type;
        if (isNodeType(f.value.type)) {
            for (const NodePtr& child : f.value.nodes) value.nodes.push_back(copyTemplate(child, env, memo));
        } else {
            value = f.value;
        }
    }
    for (const IsBinding& binding : node->is_bindings) {
        const auto it = env.find(binding.interface_field);
        if (it == env.end()) continue;  // bound to an event: no value
        if (FieldValue* existing = copy->field(binding.field)) *existing = *it->second;
        else copy->fields.push_back({binding.field, *it->second});
    }
    memo[node.get()] = copy;
    return copy;
}

// ---- traversal ------------------------------------------------------------------------------

void Vrml97Builder::visitChildren(const Node& node, std::string_view field, const DMat4& m, int depth) {
    const FieldValue* children = node.field(field);
    if (!children) return;
    openLightScope();
    for (const NodePtr& child : children->nodes) visit(child, m, depth + 1);
    closeLightScope();
}

void Vrml97Builder::openLightScope() { light_scopes_.push_back({scene_.meshes.size(), {}}); }

void Vrml97Builder::closeLightScope() {
    // The children's meshes are the ones appended since the scope opened, before or after the light.
    for (size_t light : light_scopes_.back().lights)
        scopeLight(scene_.lights[light], light_scopes_.back().first_mesh, scene_.meshes.size());
    light_scopes_.pop_back();
}

void Vrml97Builder::visit(const NodePtr& start, const DMat4& m, int depth) {
    if (!start || aborted_) return;
    if (++visits_ > vrml97Limits().max_node_visits) {
        abort(start->location, "the scene graph expands to more than " +
                                   std::to_string(vrml97Limits().max_node_visits) + " node instances (DEF/USE fan-out)");
        return;
    }
    if (depth > 4 * vrml97Limits().max_nesting) {
        abort(start->location, "scene graph nested too deeply through PROTOs");
        return;
    }
    const NodePtr node = resolve(start);
    if (!node) return;
    const std::string& type = node->type;
    if (type == "Transform") {
        const Vec3 center = sfVec3(*node, "center", Vec3(0.0f));
        const DMat4 scale_orientation = rotationMatrix(sfRotation(*node, "scaleOrientation", Vec4(0, 0, 1, 0)));
        const DMat4 local = translationMatrix(sfVec3(*node, "translation", Vec3(0.0f))) * translationMatrix(center) *
                            rotationMatrix(sfRotation(*node, "rotation", Vec4(0, 0, 1, 0))) * scale_orientation *
                            scaleMatrix(sfVec3(*node, "scale", Vec3(1.0f))) *
                            glm::transpose(scale_orientation) * translationMatrix(-center);
        visitChildren(*node, "children", m * local, depth);
    } else if (type == "Group" || type == "Collision" || type == "Billboard" || type == "Anchor") {
        visitChildren(*node, "children", m, depth);
    } else if (type == "Switch") {
        const int32_t which = sfInt(*node, "whichChoice", -1);
        const FieldValue* choice = node->field("choice");
        if (choice && which >= 0 && static_cast<size_t>(which) < choice->nodes.size())
            visit(choice->nodes[static_cast<size_t>(which)], m, depth + 1);
    } else if (type == "LOD") {
        const FieldValue* level = node->field("level");
        if (level && !level->nodes.empty()) visit(level->nodes.front(), m, depth + 1);
    } else if (type == "Shape") {
        shape(*node, m);
    } else if (type == "Inline") {
        inlineNode(*node, m);
    } else if (type == "PointLight" || type == "SpotLight" || type == "DirectionalLight") {
        light(*node, m);
    } else if (type == "Viewpoint") {
        viewpoint(*node, m);
    } else if (type == "Background") {
        background(*node);
    } else {
        // Geometry, appearance or property nodes outside a Shape carry nothing to draw.
        warnOnce("misplaced " + type, node->location, type + " node outside a Shape (or where a child is expected) ignored");
    }
}

// ---- shapes and materials -------------------------------------------------------------------

uint32_t Vrml97Builder::materialFor(const NodePtr& appearance) {
    NodePtr material;
    std::string texture;
    SourceLocation texture_location;
    if (appearance && appearance->type == "Appearance") {
        material = sfNode(*appearance, "material");
        if (material && material->type != "Material") material = nullptr;
        if (NodePtr tex = sfNode(*appearance, "texture"); tex && tex->type == "ImageTexture") {
            // The first local url (a missing file is still named: the depfile lists it).
            for (const std::string& url : mfStrings(*tex, "url"))
                if (const std::optional<std::string> resolved = resolveUrl(path_, url)) {
                    texture = *resolved;
                    texture_location = tex->location;
                    break;
                }
        }
    }
    if (!material && texture.empty()) {
        if (default_material_ == UINT32_MAX) {
            Material m;
            m.name = "default";
            m.location = {path_, 0, 0};
            default_material_ = static_cast<uint32_t>(scene_.materials.size());
            scene_.materials.push_back(std::move(m));
        }
        return default_material_;
    }
    const auto key = std::make_pair(static_cast<const Node*>(material.get()), texture);
    if (const auto it = materials_.find(key); it != materials_.end()) return it->second;
    Material m;
    if (!texture.empty()) m.base_color_texture = {.path = texture, .location = texture_location, .rgb_replaces = true};
    if (material) {
        // The Material's DEF name, else its Appearance's (scenes/cornell_box.wrl names those),
        // else where it is.
        m.name = !material->name.empty()                 ? material->name
                 : appearance && !appearance->name.empty() ? appearance->name
                                                           : "Material@" + std::to_string(material->location.line) +
                                                                 ":" + std::to_string(material->location.column);
        m.reflectance = sfVec3(*material, "diffuseColor", Vec3(0.8f));
        m.emission = sfVec3(*material, "emissiveColor", Vec3(0.0f));
        m.ambient_intensity = sfFloat(*material, "ambientIntensity", 0.2f);
        m.transparency = sfFloat(*material, "transparency", 0.0f);
        m.location = material->location;
    } else {
        m.name = !appearance->name.empty() ? appearance->name : "default";
        m.location = appearance->location;
    }
    const uint32_t index = static_cast<uint32_t>(scene_.materials.size());
    scene_.materials.push_back(std::move(m));
    materials_[key] = index;
    return index;
}

void Vrml97Builder::shape(const Node& node, const DMat4& m) {
    const NodePtr geometry = sfNode(node, "geometry");
    if (!geometry) return;
    Mesh mesh;
    const std::string& type = geometry->type;
    bool ok = false;
    std::optional<std::pair<Primitive, Vec3>> primitive;  // its kind and size, for its texture coordinates
    if (type == "IndexedFaceSet") {
        ok = indexedFaceSet(*geometry, mesh);
    } else if (type == "ElevationGrid") {
        ok = elevationGrid(*geometry, mesh);
    } else if (type == "Extrusion") {
        ok = extrusion(*geometry, mesh);
    } else if (type == "Box") {
        primitive = {Primitive::Box, sfVec3(*geometry, "size", Vec3(2.0f))};
        appendBox(mesh, primitive->second);
        ok = true;
    } else if (type == "Sphere") {
        primitive = {Primitive::Sphere, Vec3(sfFloat(*geometry, "radius", 1.0f), 0.0f, 0.0f)};
        appendSphere(mesh, primitive->second.x);
        ok = true;
    } else if (type == "Cylinder") {
        primitive = {Primitive::Cylinder, Vec3(sfFloat(*geometry, "radius", 1.0f), sfFloat(*geometry, "height", 2.0f), 0.0f)};
        appendCylinder(mesh, primitive->second.x, primitive->second.y, sfBool(*geometry, "side", true),
                       sfBool(*geometry, "top", true), sfBool(*geometry, "bottom", true));
        ok = true;
    } else if (type == "Cone") {
        primitive = {Primitive::Cone, Vec3(sfFloat(*geometry, "bottomRadius", 1.0f), sfFloat(*geometry, "height", 2.0f), 0.0f)};
        appendCone(mesh, primitive->second.x, primitive->second.y, sfBool(*geometry, "side", true),
                   sfBool(*geometry, "bottom", true));
        ok = true;
    } else {
        warnOnce("geometry " + type, geometry->location, type + " is not a geometry node; Shape ignored");
    }
    if (!ok || mesh.triangles.empty()) return;
    mesh.material = materialFor(sfNode(node, "appearance"));
    // A textured face set without texCoord gets the default mapping, a textured primitive the
    // standard's, in object space.
    const bool textured = !scene_.materials[mesh.material].base_color_texture.empty();
    if (type == "IndexedFaceSet" && mesh.uv0.empty() && textured) defaultTextureCoordinates(mesh);
    if (primitive && textured) primitiveTextureCoordinates(mesh, primitive->first, primitive->second);
    finishMesh(std::move(mesh), *geometry, m);
}

void Vrml97Builder::finishMesh(Mesh mesh, const Node& geometry, const DMat4& m) {
    triangles_ += mesh.triangles.size();
    if (triangles_ > vrml97Limits().max_triangles) {
        abort(geometry.location, "the scene has more than " + std::to_string(vrml97Limits().max_triangles) + " triangles");
        return;
    }
    if (!reserveMesh(mesh, geometry)) return;
    mesh.location = geometry.location;
    mesh.name = !geometry.name.empty() ? geometry.name : geometry.type;
    const size_t first = scene_.meshes.size();
    scene_.meshes.push_back(std::move(mesh));
    transformAppended(scene_, first, scene_.lights.size(), scene_.cameras.size(), m);
}

// ---- lights, viewpoints, inlines ---------------------------------------------------------------

void Vrml97Builder::light(const Node& node, const DMat4& m) {
    Light light;
    light.name = node.name;
    light.location = node.location;
    light.color = sfVec3(node, "color", Vec3(1.0f));
    light.intensity = sfFloat(node, "intensity", 1.0f);
    light.ambient_intensity = sfFloat(node, "ambientIntensity", 0.0f);
    light.on = sfBool(node, "on", true);
    if (node.type == "DirectionalLight") {
        light.type = LightType::Directional;
        light.direction = sfVec3(node, "direction", Vec3(0, 0, -1));
        light.radius = INFINITY;
    } else {
        light.type = node.type == "SpotLight" ? LightType::Spot : LightType::Point;
        light.position = sfVec3(node, "location", Vec3(0.0f));
        light.attenuation = sfVec3(node, "attenuation", Vec3(1, 0, 0));
        light.radius = sfFloat(node, "radius", 100.0f);
        if (light.type == LightType::Spot) {
            light.direction = sfVec3(node, "direction", Vec3(0, 0, -1));
            light.beam_width = sfFloat(node, "beamWidth", 1.570796f);
            light.cut_off_angle = sfFloat(node, "cutOffAngle", 0.785398f);
        }
    }
    const double length = glm::length(DVec3(light.direction));
    if (length > 0.0 && std::isfinite(length)) light.direction = Vec3(DVec3(light.direction) / length);
    if (light.type == LightType::Directional && !light_scopes_.empty())
        light_scopes_.back().lights.push_back(scene_.lights.size());
    scene_.lights.push_back(light);
    transformAppended(scene_, scene_.meshes.size(), scene_.lights.size() - 1, scene_.cameras.size(), m);
}

void Vrml97Builder::viewpoint(const Node& node, const DMat4& m) {
    Camera camera;
    camera.location = node.location;
    const auto& description = node.field("description");
    camera.name = description && !description->strings.empty() ? description->strings.front() : node.name;
    camera.position = sfVec3(node, "position", Vec3(0, 0, 10));
    const Vec4 r = sfRotation(node, "orientation", Vec4(0, 0, 1, 0));
    camera.orientation = Quat(glm::quat_cast(rotationMatrix(r)));
    camera.field_of_view = sfFloat(node, "fieldOfView", 0.785398f);
    scene_.cameras.push_back(camera);
    transformAppended(scene_, scene_.meshes.size(), scene_.lights.size(), scene_.cameras.size() - 1, m);
}

// The first Background is the bound one (VRML97 4.6.10); its panorama images are not read.
void Vrml97Builder::background(const Node& node) {
    if (scene_.background) return;
    BackgroundSky sky;
    sky.location = node.location;
    sky.sky_angle = mfFloats(node, "skyAngle");
    sky.ground_angle = mfFloats(node, "groundAngle");
    auto colours = [&](std::string_view name) {
        std::vector<Vec3> out;
        const std::vector<float>& f = mfFloats(node, name);
        for (size_t i = 0; i + 2 < f.size(); i += 3) out.push_back(Vec3(f[i], f[i + 1], f[i + 2]));
        return out;
    };
    sky.sky_color = colours("skyColor");
    if (sky.sky_color.empty() && !node.field("skyColor")) sky.sky_color = {Vec3(0.0f)};  // the default
    sky.ground_color = colours("groundColor");
    for (const char* url : {"backUrl", "bottomUrl", "frontUrl", "leftUrl", "rightUrl", "topUrl"})
        if (!mfStrings(node, url).empty()) {
            warnOnce("background panorama", node.location,
                     "Background panorama images (backUrl, ...) are not read: --sky background uses its colours");
            break;
        }
    scene_.background = std::move(sky);
}

void Vrml97Builder::inlineNode(const Node& node, const DMat4& m) {
    const auto& urls = mfStrings(node, "url");
    std::string missing;
    bool refused = false;
    for (const std::string& url : urls) {
        const std::optional<std::string> resolved = resolveUrl(path_, url);
        if (!resolved) continue;
        if (!mayRead(*resolved, node.location, "Inline", options_, diagnostics_)) {
            refused = true;  // warned, as missing: the next url may do
            continue;
        }
        std::error_code ec;
        if (!std::filesystem::is_regular_file(*resolved, ec)) {
            noteMissing(*resolved, options_);
            if (missing.empty()) missing = *resolved;
            continue;
        }
        const std::string key = std::filesystem::weakly_canonical(*resolved, ec).string();
        if (std::find(inline_stack_.begin(), inline_stack_.end(), key) != inline_stack_.end()) {
            diagnostics_.warning(node.location, "Inline '" + url + "' includes a file already being read; skipped");
            return;
        }
        if (static_cast<int>(inline_stack_.size()) >= vrml97Limits().max_file_depth) {
            diagnostics_.warning(node.location, "Inlines nested more than " +
                                                    std::to_string(vrml97Limits().max_file_depth) + " deep; skipped");
            return;
        }
        const std::optional<std::string> text = loadText(*resolved, node.location, options_, diagnostics_);
        if (!text) return;
        const size_t meshes = scene_.meshes.size(), lights = scene_.lights.size(), cameras = scene_.cameras.size();
        inline_stack_.push_back(key);
        readText(*text, *resolved, options_, inline_stack_, scene_, diagnostics_);
        inline_stack_.pop_back();
        transformAppended(scene_, meshes, lights, cameras, m);
        return;
    }
    if (refused && missing.empty()) return;
    const std::string message = urls.empty() ? "Inline without a url ignored"
                                : missing.empty()
                                    ? "Inline has no local url ('" + urls.front() + "'); skipped"
                                    : "Inline file '" + missing + "' not found; skipped";
    if (options_.strict && !urls.empty()) diagnostics_.error(node.location, message);
    else diagnostics_.warning(node.location, message);
}

}  // namespace radbake::vrml
