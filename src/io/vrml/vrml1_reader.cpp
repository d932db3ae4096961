// VRML 1.0 reader: entry point, node dispatch, DEF/USE, grouping and property nodes.
// Shapes, lights, cameras and inlines are in vrml1_shapes.cpp, field values in vrml1_values.cpp.
#include "io/vrml/vrml1_reader.h"

#include <cmath>
#include <exception>

#include "io/vrml/vrml1_parser.h"
#include "io/vrml/vrml_transform.h"

namespace radbake::vrml {
namespace {

Vrml1Kind kindOf(std::string_view name) {
    static const std::unordered_map<std::string_view, Vrml1Kind> kinds = {
        {"Separator", Vrml1Kind::Separator},
        {"TransformSeparator", Vrml1Kind::TransformSeparator},
        {"Group", Vrml1Kind::Group},
        {"Switch", Vrml1Kind::Switch},
        {"LOD", Vrml1Kind::Lod},
        {"WWWAnchor", Vrml1Kind::WwwAnchor},
        {"Coordinate3", Vrml1Kind::Coordinate3},
        {"Material", Vrml1Kind::Material},
        {"MaterialBinding", Vrml1Kind::MaterialBinding},
        {"ShapeHints", Vrml1Kind::ShapeHints},
        {"Transform", Vrml1Kind::Transform},
        {"MatrixTransform", Vrml1Kind::MatrixTransform},
        {"Translation", Vrml1Kind::Translation},
        {"Rotation", Vrml1Kind::Rotation},
        {"Scale", Vrml1Kind::Scale},
        {"IndexedFaceSet", Vrml1Kind::IndexedFaceSet},
        {"Cube", Vrml1Kind::Cube},
        {"Sphere", Vrml1Kind::Sphere},
        {"Cylinder", Vrml1Kind::Cylinder},
        {"Cone", Vrml1Kind::Cone},
        {"WWWInline", Vrml1Kind::WwwInline},
        {"PerspectiveCamera", Vrml1Kind::PerspectiveCamera},
        {"PointLight", Vrml1Kind::PointLight},
        {"DirectionalLight", Vrml1Kind::DirectionalLight},
        {"SpotLight", Vrml1Kind::SpotLight},
        {"Texture2", Vrml1Kind::Texture2},
        // Nothing a radiosity bake uses: read and set aside without a word.
        {"Info", Vrml1Kind::Accepted},
        {"Normal", Vrml1Kind::Accepted},
        {"NormalBinding", Vrml1Kind::Accepted},
        {"TextureCoordinate2", Vrml1Kind::TextureCoordinate2},
        {"Texture2Transform", Vrml1Kind::Accepted},
        {"OrthographicCamera", Vrml1Kind::Accepted},
        {"FontStyle", Vrml1Kind::Accepted},
        // Geometry without area: nothing to light.
        {"IndexedLineSet", Vrml1Kind::Ignored},
        {"PointSet", Vrml1Kind::Ignored},
        {"AsciiText", Vrml1Kind::Ignored},
    };
    const auto it = kinds.find(name);
    return it == kinds.end() ? Vrml1Kind::Unknown : it->second;
}

bool parseBinding(std::string_view value, Vrml1Binding& binding) {
    static const std::unordered_map<std::string_view, Vrml1Binding> values = {
        {"DEFAULT", Vrml1Binding::Overall},          {"OVERALL", Vrml1Binding::Overall},
        {"PER_PART", Vrml1Binding::PerPart},         {"PER_PART_INDEXED", Vrml1Binding::PerPartIndexed},
        {"PER_FACE", Vrml1Binding::PerFace},         {"PER_FACE_INDEXED", Vrml1Binding::PerFaceIndexed},
        {"PER_VERTEX", Vrml1Binding::PerVertex},     {"PER_VERTEX_INDEXED", Vrml1Binding::PerVertexIndexed},
    };
    const auto it = values.find(value);
    if (it == values.end()) return false;
    binding = it->second;
    return true;
}

}  // namespace

Vrml1Parser::Vrml1Parser(std::string_view text, const std::string& path, const VrmlOptions& options,
                         std::vector<std::string>& inline_stack, Scene& scene, Diagnostics& diagnostics)
    : text_(text),
      path_(path),
      options_(options),
      inline_stack_(inline_stack),
      scene_(scene),
      diagnostics_(diagnostics),
      root_lexer_(text, path),
      replay_budget_(kReplayTokenBudget + 16 * static_cast<uint64_t>(text.size())) {}

bool Vrml1Parser::parseFile() {
    // The header line is a '#' comment to the lexer. The file holds one node by the
    // specification; many hold several, read as if in one Separator.
    Vrml1State root;
    light_frames_.emplace_back();
    while (peek().kind != TokenKind::End) {
        const Token first = next();
        if (!parseNode(first, root, 0)) return false;
    }
    closeLightFrame();
    for (const auto& [message, place] : repeated_)
        if (place.second > 0)
            diagnostics_.note(place.first, message + ": " + std::to_string(place.second) +
                                               " more occurrence(s) in this file not reported");
    return !failed_;
}

void Vrml1Parser::closeLightFrame() {
    for (const auto& [light, first_mesh] : light_frames_.back())
        scopeLight(scene_.lights[light], first_mesh, scene_.meshes.size());
    light_frames_.pop_back();
}

bool Vrml1Parser::isNodeStart(const Token& word) {
    return word.kind == TokenKind::Word &&
           (word.text == "DEF" || word.text == "USE" || peek().kind == TokenKind::OpenBrace);
}

bool Vrml1Parser::parseNode(const Token& first, Vrml1State& state, int depth) {
    if (depth > kMaxDepth) return fail(first, "nodes nested deeper than " + std::to_string(kMaxDepth) + " levels");
    if (first.kind != TokenKind::Word) return fail(first, "expected a node, found " + describe(first));
    if (first.text == "USE") return parseUse(state, depth);
    std::string def_name;
    Token type = first;
    if (first.text == "DEF") {
        const Token name = next();
        if (name.kind != TokenKind::Word && name.kind != TokenKind::Number)
            return fail(name, "expected a name after DEF, found " + describe(name));
        def_name = std::string(name.text);
        type = next();
        if (type.kind != TokenKind::Word)
            return fail(type, "expected a node type after 'DEF " + def_name + "', found " + describe(type));
    }
    if (!parseNodeOfType(type, def_name, state, depth)) return false;
    // A DEF names the node once it is complete, so a USE inside it means an earlier DEF:
    // re-reads can never loop.
    if (!def_name.empty() && replay_ == 0) {
        const SourceLocation where = loc(type);
        defs_.push_back({offsetOf(type), where.line, where.column, def_name});
        names_[def_name] = defs_.size() - 1;
    }
    return true;
}

bool Vrml1Parser::parseUse(Vrml1State& state, int depth) {
    const Token name = next();
    if (name.kind != TokenKind::Word && name.kind != TokenKind::Number)
        return fail(name, "expected a name after USE, found " + describe(name));
    size_t def_index = 0;
    if (replay_ == 0) {
        const auto it = names_.find(std::string(name.text));
        if (it == names_.end()) {
            const std::string message = "USE of undefined name '" + std::string(name.text) + "'";
            if (options_.strict) return fail(name, message);
            warn(name, message + " ignored");
            return true;
        }
        def_index = it->second;
        use_targets_[offsetOf(name)] = def_index;
    } else {
        const auto it = use_targets_.find(offsetOf(name));
        if (it == use_targets_.end()) return true;  // was undefined on the first pass
        def_index = it->second;
    }
    if (!emit_) return true;  // nothing drawn here, and re-reading defines nothing new

    const DefRecord def = defs_[def_index];
    Lexer lexer(text_.substr(def.offset), path_);
    Lexer* saved_lexer = lexer_;
    const int saved_line = base_line_, saved_column = base_column_;
    lexer_ = &lexer;
    base_line_ = def.line;
    base_column_ = def.column;
    ++replay_;
    const Token type = next();
    const bool ok = parseNodeOfType(type, def.name, state, depth + 1);
    --replay_;
    lexer_ = saved_lexer;
    base_line_ = saved_line;
    base_column_ = saved_column;
    return ok;
}

bool Vrml1Parser::parseNodeOfType(const Token& type, const std::string& def_name, Vrml1State& state, int depth) {
    if (depth > kMaxDepth) return fail(type, "nodes nested deeper than " + std::to_string(kMaxDepth) + " levels");
    if (replay_ > 0 && replay_tokens_ > replay_budget_)
        return fail(type, "USE expansion too large (over " + std::to_string(replay_budget_) +
                              " tokens re-read): nested DEF/USE chain");
    Vrml1Kind kind = kindOf(type.text);
    const Token open = next();
    if (open.kind != TokenKind::OpenBrace)
        return fail(open, "expected '{' after node type '" + std::string(type.text) + "', found " + describe(open));
    // Fields declared by this node's `fields [...]` are its own business: skipped quietly.
    std::set<std::string> outer_declared = std::move(declared_);
    declared_.clear();
    const bool ok = readDescription(kind) && parseNodeBody(kind, type, def_name, state, depth);
    declared_ = std::move(outer_declared);
    return ok;
}

bool Vrml1Parser::readDescription(Vrml1Kind& kind) {
    // Any node may begin with `fields [ SFFloat width, MFColor diffuseColor, ... ]` and an
    // extension node with `isA [ "Material" ]`, naming the standard node it extends: read it
    // as that node.
    for (;;) {
        const Token& p = peek();
        if (p.kind != TokenKind::Word || (p.text != "fields" && p.text != "isA")) return true;
        const Token word = next();
        const Token open = next();
        if (open.kind != TokenKind::OpenBracket)
            return fail(open, "'" + std::string(word.text) + "' must be followed by '['");
        for (;;) {
            const Token t = next();
            if (t.kind == TokenKind::CloseBracket) break;
            if (t.kind == TokenKind::End || t.kind == TokenKind::OpenBrace || t.kind == TokenKind::CloseBrace ||
                t.kind == TokenKind::OpenBracket)
                return fail(open, "'" + std::string(word.text) + " [' without a matching ']'");
            if (word.text == "fields") {
                const Token name = next();
                if (t.kind != TokenKind::Word || name.kind != TokenKind::Word)
                    return fail(t, "'fields' expects pairs of a field type and a field name");
                declared_.insert(std::string(name.text));
            } else if (kind == Vrml1Kind::Unknown && t.kind == TokenKind::String) {
                const Vrml1Kind base = kindOf(Lexer::decodeString(t));
                if (base != Vrml1Kind::Unknown) kind = base;
            }
        }
    }
}

bool Vrml1Parser::parseNodeBody(Vrml1Kind kind, const Token& type, const std::string& def_name, Vrml1State& state,
                                int depth) {
    switch (kind) {
        case Vrml1Kind::Separator:
        case Vrml1Kind::Lod:
        case Vrml1Kind::WwwAnchor: {
            Vrml1State inner = state;  // state changes stay inside, and so do lights
            if (!def_name.empty()) inner.group_name = def_name;
            light_frames_.emplace_back();
            const bool ok = parseGroup(kind, type, inner, depth);
            closeLightFrame();
            return ok;
        }
        case Vrml1Kind::TransformSeparator:
        case Vrml1Kind::Group:
        case Vrml1Kind::Switch: {
            // Only the transform (TransformSeparator) and the name of the group are restored.
            const DMat4 saved_matrix = state.world_from_object;
            std::string saved_name = state.group_name;
            if (!def_name.empty()) state.group_name = def_name;
            const bool ok = parseGroup(kind, type, state, depth);
            if (kind == Vrml1Kind::TransformSeparator) state.world_from_object = saved_matrix;
            state.group_name = std::move(saved_name);
            return ok;
        }
        case Vrml1Kind::IndexedFaceSet: return parseIndexedFaceSet(type, def_name, state, depth);
        case Vrml1Kind::Cube:
        case Vrml1Kind::Sphere:
        case Vrml1Kind::Cylinder:
        case Vrml1Kind::Cone: return parsePrimitive(kind, type, def_name, state, depth);
        case Vrml1Kind::PointLight:
        case Vrml1Kind::DirectionalLight:
        case Vrml1Kind::SpotLight: return parseLight(kind, type, state, depth);
        case Vrml1Kind::PerspectiveCamera: return parseCamera(type, def_name, state, depth);
        case Vrml1Kind::WwwInline: return parseInline(type, state, depth);
        case Vrml1Kind::Accepted: return skipBody(type);
        case Vrml1Kind::Ignored:
            warnOnce("ignored:" + std::string(type.text), type,
                     std::string(type.text) + " ignored (no surface to light); further ones are not reported");
            return skipBody(type);
        case Vrml1Kind::Unknown: return parseUnknown(type);
        default: return parseProperty(kind, type, def_name, state, depth);
    }
}

bool Vrml1Parser::parseChildInScratch(const Token& first, const Vrml1State& state, int depth) {
    // A child that is not drawn is still read (its DEFs count) but changes no state and
    // emits nothing.
    Vrml1State scratch = state;
    const bool saved_emit = emit_;
    emit_ = false;
    const bool ok = parseNode(first, scratch, depth + 1);
    emit_ = saved_emit;
    return ok;
}

bool Vrml1Parser::parseGroup(Vrml1Kind kind, const Token& type, Vrml1State& state, int depth) {
    // Switch draws child whichChild (-1 none, -3 all); LOD draws its first level.
    int32_t which = kind == Vrml1Kind::Switch ? -1 : (kind == Vrml1Kind::Lod ? 0 : -3);
    int child = 0;
    for (;;) {
        const Token& p = peek();
        if (p.kind == TokenKind::CloseBrace) {
            next();
            return true;
        }
        if (p.kind == TokenKind::End) return fail(type, std::string(type.text) + " has no closing '}'");
        const Token word = next();
        if (word.kind != TokenKind::Word)
            return fail(word, "expected a field or a child node in " + std::string(type.text) + ", found " +
                                  describe(word));
        bool ok = true;
        if (isNodeStart(word)) {
            const bool drawn = which == -3 || which == child;
            ++child;
            ok = drawn ? parseNode(word, state, depth + 1) : parseChildInScratch(word, state, depth);
        } else if (kind == Vrml1Kind::Switch && word.text == "whichChild") {
            ok = readInt(word, which);
        } else if ((kind == Vrml1Kind::Separator && word.text == "renderCulling") ||
                   (kind == Vrml1Kind::Lod && (word.text == "range" || word.text == "center")) ||
                   (kind == Vrml1Kind::WwwAnchor &&
                    (word.text == "name" || word.text == "description" || word.text == "map"))) {
            ok = skipValue(word);
        } else {
            ok = unknownField(word, type.text);
        }
        if (!ok) return false;
    }
}

bool Vrml1Parser::parseProperty(Vrml1Kind kind, const Token& type, const std::string& def_name, Vrml1State& state,
                                int depth) {
    auto r = [](bool ok) { return ok ? 1 : -1; };
    switch (kind) {
        case Vrml1Kind::Coordinate3: {
            auto points = std::make_shared<std::vector<Vec3>>();
            const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
                return f.text == "point" ? r(readVec3s(f, *points)) : 0;
            });
            state.coords = std::move(points);
            return ok;
        }
        case Vrml1Kind::Material: {
            auto list = std::make_shared<Vrml1MaterialList>();
            list->key = offsetOf(type);
            list->name = def_name.empty() ? "Material" : def_name;
            list->location = loc(type);
            std::vector<float> floats;
            const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
                if (f.text == "ambientColor") return r(readVec3s(f, list->ambient));
                if (f.text == "diffuseColor") return r(readVec3s(f, list->diffuse));
                if (f.text == "specularColor") return r(readVec3s(f, list->specular));
                if (f.text == "emissiveColor") return r(readVec3s(f, list->emissive));
                if (f.text == "shininess") return r(readFloats(f, list->shininess));
                if (f.text == "transparency") return r(readFloats(f, list->transparency));
                return 0;
            });
            // An empty list means the field's default.
            if (list->ambient.empty()) list->ambient = {Vec3(0.2f)};
            if (list->diffuse.empty()) list->diffuse = {Vec3(0.8f)};
            if (list->specular.empty()) list->specular = {Vec3(0.0f)};
            if (list->emissive.empty()) list->emissive = {Vec3(0.0f)};
            if (list->shininess.empty()) list->shininess = {0.2f};
            if (list->transparency.empty()) list->transparency = {0.0f};
            state.material = std::move(list);
            return ok;
        }
        case Vrml1Kind::MaterialBinding:
            return parseLeaf(type, state, depth, [&](const Token& f) {
                if (f.text != "value") return 0;
                std::string value;
                if (!readWord(f, value)) return -1;
                if (!parseBinding(value, state.material_binding)) {
                    if (options_.strict) return r(fail(f, "unknown MaterialBinding value '" + value + "'"));
                    warn(f, "unknown MaterialBinding value '" + value + "' ignored");
                }
                return 1;
            });
        case Vrml1Kind::ShapeHints:
            return parseLeaf(type, state, depth, [&](const Token& f) {
                std::string value;
                if (f.text == "creaseAngle") return r(readFloat(f, state.crease_angle));
                if (f.text != "vertexOrdering" && f.text != "shapeType" && f.text != "faceType") return 0;
                if (!readWord(f, value)) return -1;
                if (f.text == "vertexOrdering") {
                    state.ordering_known = value == "CLOCKWISE" || value == "COUNTERCLOCKWISE";
                    state.clockwise = value == "CLOCKWISE";
                } else if (f.text == "shapeType") {
                    state.solid_shape = value == "SOLID";
                } else {
                    state.convex_faces = value == "CONVEX";
                }
                return 1;
            });
        case Vrml1Kind::Transform: {
            Vec3 translation(0.0f), scale(1.0f), center(0.0f);
            DVec3 rotation_axis(0, 0, 1), scale_axis(0, 0, 1);
            double rotation_angle = 0.0, scale_angle = 0.0;
            const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
                if (f.text == "translation") return r(readVec3(f, translation));
                if (f.text == "rotation") return r(readRotation(f, rotation_axis, rotation_angle));
                if (f.text == "scaleFactor") return r(readVec3(f, scale));
                if (f.text == "scaleOrientation") return r(readRotation(f, scale_axis, scale_angle));
                if (f.text == "center") return r(readVec3(f, center));
                return 0;
            });
            // T C R SR S -SR -C, as VRML97's Transform.
            const DMat4 sr = rotationMatrix(scale_axis, scale_angle);
            state.world_from_object = state.world_from_object * translationMatrix(translation) *
                                      translationMatrix(center) * rotationMatrix(rotation_axis, rotation_angle) *
                                      sr * scaleMatrix(scale) * glm::transpose(sr) * translationMatrix(-center);
            return ok;
        }
        case Vrml1Kind::MatrixTransform: {
            DMat4 matrix(1.0);
            const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
                return f.text == "matrix" ? r(readMatrix(f, matrix)) : 0;
            });
            state.world_from_object = state.world_from_object * matrix;
            return ok;
        }
        case Vrml1Kind::Translation: {
            Vec3 translation(0.0f);
            const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
                return f.text == "translation" ? r(readVec3(f, translation)) : 0;
            });
            state.world_from_object = state.world_from_object * translationMatrix(translation);
            return ok;
        }
        case Vrml1Kind::Rotation: {
            DVec3 axis(0, 0, 1);
            double angle = 0.0;
            const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
                return f.text == "rotation" ? r(readRotation(f, axis, angle)) : 0;
            });
            state.world_from_object = state.world_from_object * rotationMatrix(axis, angle);
            return ok;
        }
        case Vrml1Kind::Scale: {
            Vec3 scale(1.0f);
            const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
                return f.text == "scaleFactor" ? r(readVec3(f, scale)) : 0;
            });
            state.world_from_object = state.world_from_object * scaleMatrix(scale);
            return ok;
        }
        case Vrml1Kind::TextureCoordinate2: {
            std::vector<float> values;
            const bool ok = parseLeaf(type, state, depth, [&](const Token& f) {
                return f.text == "point" ? r(readFloats(f, values)) : 0;
            });
            auto points = std::make_shared<std::vector<Vec2>>();
            for (size_t i = 0; i + 1 < values.size(); i += 2) points->emplace_back(values[i], values[i + 1]);
            state.tex_coords = std::move(points);
            return ok;
        }
        case Vrml1Kind::Texture2:
            state.texture_location = loc(type);
            return parseLeaf(type, state, depth, [&](const Token& f) {
                if (f.text == "filename") return r(readString(f, state.texture));
                if (f.text == "image" || f.text == "wrapS" || f.text == "wrapT") return r(skipValue(f));
                return 0;
            });
        default: return fail(type, "internal: node '" + std::string(type.text) + "' has no reader");
    }
}

bool Vrml1Parser::parseUnknown(const Token& type) {
    // VRML 1.0 extension nodes describe their fields (`fields [ SFFloat a, ... ]`); the body is
    // skipped by its braces and brackets, which covers that description and any children.
    const std::string message = "unknown node type '" + std::string(type.text) + "'";
    if (options_.strict) return fail(type, message);
    warn(type, message + " skipped");
    return skipBody(type);
}

bool readVrml1(std::string_view text, const std::string& path, const VrmlOptions& options,
               std::vector<std::string>& inline_stack, Scene& scene, Diagnostics& diagnostics) {
    // No exception leaves the reader: out of memory on a hostile file becomes a located error.
    try {
        Vrml1Parser parser(text, path, options, inline_stack, scene, diagnostics);
        return parser.parseFile();
    } catch (const std::exception& e) {
        diagnostics.error({path, 0, 0}, std::string("VRML 1.0 reader failed: ") + e.what());
        return false;
    }
}

}  // namespace radbake::vrml
