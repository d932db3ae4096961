#pragma once
// VRML97 scene builder: node graph -> Scene (meshes in this file's world space, materials,
// lights, cameras). Expands PROTO instances and reads Inlines.
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "io/vrml/vrml97_nodes.h"
#include "io/vrml/vrml_reader.h"

namespace radbake::vrml {

// The default texture coordinates of an IndexedFaceSet without texCoord (object space).
void defaultTextureCoordinates(Mesh& mesh);

// Reads VRML97 text (header included) from `path`; the entry point vrml::readText uses.
bool readVrml97(std::string_view text, const std::string& path, const VrmlOptions& options,
                std::vector<std::string>& inline_stack, Scene& scene, Diagnostics& diagnostics);

class Vrml97Builder {
public:
    Vrml97Builder(std::string path, const VrmlOptions& options, std::vector<std::string>& inline_stack,
                  Scene& scene, Diagnostics& diagnostics);
    // False when a limit was hit or an error reported while building.
    bool build(const std::vector<NodePtr>& roots);

private:
    void visit(const NodePtr& node, const DMat4& world_from_object, int depth);
    void visitChildren(const Node& node, std::string_view field, const DMat4& m, int depth);
    NodePtr resolve(const NodePtr& node);
    NodePtr expand(const Node& instance);
    NodePtr copyTemplate(const NodePtr& node, const std::unordered_map<std::string, const FieldValue*>& env,
                         std::unordered_map<const Node*, NodePtr>& memo);
    void abort(const SourceLocation& where, const std::string& message);

    void shape(const Node& node, const DMat4& m);
    void inlineNode(const Node& node, const DMat4& m);
    void light(const Node& node, const DMat4& m);
    void viewpoint(const Node& node, const DMat4& m);
    void background(const Node& node);
    uint32_t materialFor(const NodePtr& appearance);
    void finishMesh(Mesh mesh, const Node& geometry, const DMat4& m);

    // Geometry (vrml97_geometry.cpp): fill `mesh` in object space; false when nothing to add.
    bool indexedFaceSet(const Node& node, Mesh& mesh);
    bool elevationGrid(const Node& node, Mesh& mesh);
    bool extrusion(const Node& node, Mesh& mesh);

    // Memory (vrml97_budget.cpp): what the graph below a node expands to once every USE and
    // PROTO is expanded, estimated before anything is built.
    struct Expansion {
        double meshes = 0.0, triangles = 0.0, bytes = 0.0;
        void add(const Expansion& e) {
            meshes += e.meshes;
            triangles += e.triangles;
            bytes += e.bytes;
        }
    };
    bool expansionFits(const std::vector<NodePtr>& roots);
    Expansion expansionOf(const NodePtr& node, int depth);
    Expansion geometryExpansion(const Node& geometry) const;
    std::vector<NodePtr> expandedChildren(const Node& node) const;
    void reportExpansion(const std::vector<NodePtr>& roots, const std::vector<Expansion>& sizes);
    bool reserveMesh(const Mesh& mesh, const Node& geometry);

    // Field access that tolerates missing fields and mismatched IS bindings.
    float sfFloat(const Node& node, std::string_view name, float fallback) const;
    bool sfBool(const Node& node, std::string_view name, bool fallback) const;
    int32_t sfInt(const Node& node, std::string_view name, int32_t fallback) const;
    Vec3 sfVec3(const Node& node, std::string_view name, Vec3 fallback) const;
    Vec4 sfRotation(const Node& node, std::string_view name, Vec4 fallback) const;
    const std::vector<float>& mfFloats(const Node& node, std::string_view name) const;
    const std::vector<int32_t>& mfInts(const Node& node, std::string_view name) const;
    const std::vector<std::string>& mfStrings(const Node& node, std::string_view name) const;
    NodePtr sfNode(const Node& node, std::string_view name);
    void warnOnce(const std::string& key, const SourceLocation& where, const std::string& message);

    std::string path_;
    const VrmlOptions& options_;
    std::vector<std::string>& inline_stack_;
    Scene& scene_;
    Diagnostics& diagnostics_;
    std::map<std::pair<const Node*, std::string>, uint32_t> materials_;
    uint32_t default_material_ = UINT32_MAX;
    std::unordered_map<std::string, bool> warned_;
    size_t visits_ = 0;
    size_t triangles_ = 0;  // in the scene, for the size limit
    size_t expanded_nodes_ = 0;
    bool aborted_ = false;
    std::unordered_map<const Node*, Expansion> expansions_;  // resolved node -> what it expands to
    std::vector<uint32_t> loop_;  // scratch polygon
    // Per open grouping node (and the file's top level): the meshes it started at and its
    // DirectionalLights, which light only its children (ISO/IEC 14772-1, DirectionalLight).
    struct LightScope {
        size_t first_mesh = 0;
        std::vector<size_t> lights;
    };
    std::vector<LightScope> light_scopes_;
    void openLightScope();
    void closeLightScope();
};

}  // namespace radbake::vrml
