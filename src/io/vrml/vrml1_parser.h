#pragma once
// Internal to the VRML 1.0 reader (vrml1_*.cpp): the traversal state and the parser.
//
// VRML 1.0 is a state machine: property nodes (Coordinate3, Material, Transform, ...) change
// the traversal state, shapes are built from it, Separators save and restore it. The parser
// therefore applies each node as it reads it. A USE re-reads the text of its DEF node (with a
// second lexer over the same buffer) in the state current at the USE; every USE name met on
// the first pass records which DEF it meant, so re-reading resolves names as the file did.
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "io/vrml/lexer.h"
#include "io/vrml/vrml_reader.h"

namespace radbake::vrml {

enum class Vrml1Binding { Overall, PerPart, PerPartIndexed, PerFace, PerFaceIndexed, PerVertex, PerVertexIndexed };

// A Material node: every field is a list; material i takes entry i of each list (or the
// first entry when that list is shorter).
struct Vrml1MaterialList {
    std::vector<Vec3> ambient{Vec3(0.2f)};
    std::vector<Vec3> diffuse{Vec3(0.8f)};
    std::vector<Vec3> specular{Vec3(0.0f)};
    std::vector<Vec3> emissive{Vec3(0.0f)};
    std::vector<float> shininess{0.2f};
    std::vector<float> transparency{0.0f};
    size_t key = SIZE_MAX;  // text offset of the Material node: the same for every USE of it
    std::string name;
    SourceLocation location;

    size_t count() const;  // the longest list
};

struct Vrml1State {
    DMat4 world_from_object{1.0};
    std::shared_ptr<const std::vector<Vec3>> coords;
    std::shared_ptr<const Vrml1MaterialList> material;  // null: the default material
    Vrml1Binding material_binding = Vrml1Binding::Overall;
    // ShapeHints
    bool ordering_known = false;
    bool clockwise = false;
    bool solid_shape = false;
    bool convex_faces = true;
    float crease_angle = 0.5f;
    std::string texture;  // Texture2 filename as written, noted on materials
    SourceLocation texture_location;
    std::shared_ptr<const std::vector<Vec2>> tex_coords;  // TextureCoordinate2
    std::string group_name;  // DEF name of the nearest named group: names the shapes inside it
};

// Triangles of one shape in object space, before they are split by material.
struct Vrml1Shape {
    const std::vector<Vec3>* positions = nullptr;
    std::vector<UVec3> triangles;
    std::vector<uint32_t> triangle_polygon;  // contiguous polygon ids from 0
    std::vector<uint32_t> polygon_material;  // index into the current Material's lists
    std::vector<UVec3> triangle_uv;          // per triangle corner, index into the state's tex_coords; empty: none
    bool convex_solid = false;
    bool solid = true;
    bool clockwise = false;  // triangles turn clockwise seen from the front
    float crease_angle = 0.5f;
};

enum class Vrml1Kind {
    Unknown,
    Separator, TransformSeparator, Group, Switch, Lod, WwwAnchor,
    Coordinate3, Material, MaterialBinding, ShapeHints,
    Transform, MatrixTransform, Translation, Rotation, Scale,
    IndexedFaceSet, Cube, Sphere, Cylinder, Cone,
    WwwInline, PerspectiveCamera, PointLight, DirectionalLight, SpotLight,
    Texture2, TextureCoordinate2,
    Accepted,  // accepted and ignored: Info, Normal, NormalBinding, Texture2Transform, ...
    Ignored,             // ignored with one warning per kind: IndexedLineSet, PointSet, AsciiText
};

class Vrml1Parser {
public:
    Vrml1Parser(std::string_view text, const std::string& path, const VrmlOptions& options,
                std::vector<std::string>& inline_stack, Scene& scene, Diagnostics& diagnostics);

    bool parseFile();

private:
    // Nesting bound (groups and USE re-reads): keeps hostile input from exhausting the stack.
    static constexpr int kMaxDepth = 200;
    // Tokens that USE re-reads may consume in one file, beyond 16 per byte of the file (a
    // file has at most one token per two bytes, so its DEFs may be re-read 32 times over):
    // bounds a chain of DEFs that each USE the previous one twice (exponential growth) to
    // well under a second and ~150 MB of small meshes.
    static constexpr uint64_t kReplayTokenBudget = 2'000'000;

    struct DefRecord {
        size_t offset = 0;  // of the node type token
        int line = 0, column = 0;
        std::string name;
    };

    // tokens and diagnostics (vrml1_values.cpp)
    Token next();
    const Token& peek();
    size_t offsetOf(const Token& token) const { return static_cast<size_t>(token.text.data() - text_.data()); }
    SourceLocation loc(const Token& token) const;
    bool fail(const Token& token, const std::string& message);
    void warn(const Token& token, const std::string& message);
    void warnOnce(const std::string& key, const Token& token, const std::string& message);
    static std::string describe(const Token& token);

    // values (vrml1_values.cpp); `field` names the field in messages
    bool readFloat(const Token& field, float& value);
    bool readInt(const Token& field, int32_t& value);
    bool readBool(const Token& field, bool& value);
    bool readVec2(const Token& field, Vec2& value);
    bool readVec3(const Token& field, Vec3& value);
    bool readRotation(const Token& field, DVec3& axis, double& angle);
    bool readMatrix(const Token& field, DMat4& value);
    bool readWord(const Token& field, std::string& value);
    bool readString(const Token& field, std::string& value);
    bool readBitMask(const Token& field, std::vector<std::string>& names);
    bool readFloats(const Token& field, std::vector<float>& values);
    bool readInts(const Token& field, std::vector<int32_t>& values);
    bool readVec3s(const Token& field, std::vector<Vec3>& values);
    bool skipValue(const Token& field);   // a value of unknown type, by its shape
    bool skipBody(const Token& type);     // after '{': up to the matching '}'
    bool unknownField(const Token& field, std::string_view node);

    // nodes (vrml1_reader.cpp)
    bool parseNode(const Token& first, Vrml1State& state, int depth);
    bool parseNodeOfType(const Token& type, const std::string& def_name, Vrml1State& state, int depth);
    bool readDescription(Vrml1Kind& kind);
    bool parseNodeBody(Vrml1Kind kind, const Token& type, const std::string& def_name, Vrml1State& state,
                       int depth);
    bool parseUse(Vrml1State& state, int depth);
    bool parseGroup(Vrml1Kind kind, const Token& type, Vrml1State& state, int depth);
    bool parseChildInScratch(const Token& first, const Vrml1State& state, int depth);
    bool isNodeStart(const Token& word);
    template <typename FieldFn>
    bool parseLeaf(const Token& type, const Vrml1State& state, int depth, FieldFn on_field);
    bool parseProperty(Vrml1Kind kind, const Token& type, const std::string& def_name, Vrml1State& state,
                       int depth);
    bool parseUnknown(const Token& type);

    // shapes, lights, cameras, inlines (vrml1_shapes.cpp)
    bool parseIndexedFaceSet(const Token& type, const std::string& def_name, Vrml1State& state, int depth);
    bool parsePrimitive(Vrml1Kind kind, const Token& type, const std::string& def_name, Vrml1State& state,
                        int depth);
    bool parseLight(Vrml1Kind kind, const Token& type, Vrml1State& state, int depth);
    bool parseCamera(const Token& type, const std::string& def_name, Vrml1State& state, int depth);
    bool parseInline(const Token& type, Vrml1State& state, int depth);
    void emitShape(const Vrml1Shape& shape, const Vrml1State& state, const std::string& name,
                   const SourceLocation& where);
    uint32_t sceneMaterial(const Vrml1State& state, uint32_t index);

    std::string_view text_;
    std::string path_;
    const VrmlOptions& options_;
    std::vector<std::string>& inline_stack_;
    Scene& scene_;
    Diagnostics& diagnostics_;

    Lexer root_lexer_;
    Lexer* lexer_ = &root_lexer_;
    int replay_ = 0;              // > 0 while re-reading a DEF for a USE: no new DEFs, no diagnostics
    int base_line_ = 1, base_column_ = 1;  // where the current lexer's text starts in the file
    uint64_t replay_budget_ = kReplayTokenBudget;
    uint64_t replay_tokens_ = 0;
    bool emit_ = true;            // false inside Switch/LOD children that are not drawn
    bool failed_ = false;
    // Per open Separator (and the file): its lights, each with the first mesh after it. A
    // VRML 1.0 light lights what follows it, up to the end of its Separator.
    std::vector<std::vector<std::pair<size_t, size_t>>> light_frames_;
    void closeLightFrame();

    std::vector<DefRecord> defs_;
    std::unordered_map<std::string, size_t> names_;    // DEF name -> latest DefRecord
    std::unordered_map<size_t, size_t> use_targets_;   // offset of a USE's name -> DefRecord
    std::set<std::string> warned_;                     // keys of once-only warnings
    std::set<std::string> declared_;                   // fields the current node declared
    std::map<std::string, std::pair<SourceLocation, int>> repeated_;  // warning -> first place, repeats
    std::map<std::tuple<size_t, uint32_t, std::string>, uint32_t> materials_;  // -> Scene::materials
};

template <typename FieldFn>
inline bool Vrml1Parser::parseLeaf(const Token& type, const Vrml1State& state, int depth, FieldFn on_field) {
    // on_field(field) returns 1 when it read the field, 0 when the field is unknown, -1 on error.
    for (;;) {
        const Token& p = peek();
        if (p.kind == TokenKind::CloseBrace) {
            next();
            return true;
        }
        if (p.kind == TokenKind::End) return fail(type, std::string(type.text) + " has no closing '}'");
        const Token word = next();
        if (word.kind != TokenKind::Word)
            return fail(word, "expected a field of " + std::string(type.text) + ", found " + describe(word));
        if (isNodeStart(word)) {
            const std::string message = std::string(type.text) + " cannot hold child nodes";
            if (options_.strict) return fail(word, message);
            warn(word, message + "; child ignored");
            if (!parseChildInScratch(word, state, depth)) return false;
            continue;
        }
        const int result = on_field(word);
        if (result < 0) return false;
        if (result == 0 && !unknownField(word, type.text)) return false;
    }
}

}  // namespace radbake::vrml
