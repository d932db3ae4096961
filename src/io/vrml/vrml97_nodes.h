#pragma once
// The VRML97 node model: what the parser produces and the scene builder reads. Nodes are
// shared (DEF/USE) through shared_ptr; a DEF name is registered only after its node is
// complete, so a node can never contain itself and the graph is acyclic.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"

namespace radbake::vrml {

enum class FieldType : uint8_t {
    SFBool, SFInt32, SFFloat, SFTime, SFVec2f, SFVec3f, SFRotation, SFColor, SFString, SFImage, SFNode,
    MFBool, MFInt32, MFFloat, MFTime, MFVec2f, MFVec3f, MFRotation, MFColor, MFString, MFNode,
};

bool parseFieldType(std::string_view name, FieldType& type);
bool isMultiple(FieldType type);
// Numbers per value of a numeric type (3 for SFVec3f/MFVec3f, ...); 0 for strings and nodes.
int arity(FieldType type);
bool isFloatType(FieldType type);  // stored in FieldValue::floats
bool isNodeType(FieldType type);

struct Node;
using NodePtr = std::shared_ptr<Node>;
struct ProtoDef;

// One field's value; numeric values are flattened (an MFVec3f of n points holds 3n floats).
struct FieldValue {
    FieldType type = FieldType::SFBool;
    std::vector<float> floats;         // Float, Time, Vec2f, Vec3f, Rotation, Color
    std::vector<int32_t> ints;         // Bool (0/1), Int32, Image (width, height, components, pixels...)
    std::vector<std::string> strings;  // String
    std::vector<NodePtr> nodes;        // Node; a null pointer for NULL
};

struct Field {
    std::string name;
    FieldValue value;
};

// `field IS interface_field` inside a PROTO body.
struct IsBinding {
    std::string field;
    std::string interface_field;
};

struct Node {
    std::string type;  // built-in node type, or the PROTO name for a PROTO instance
    std::string name;  // DEF name, empty when none
    SourceLocation location;
    std::vector<Field> fields;  // only the fields the file gives
    std::vector<IsBinding> is_bindings;
    bool subtree_has_is = false;             // this node or one below it has an IS binding
    std::shared_ptr<const ProtoDef> proto;   // set for PROTO instances
    NodePtr expansion;                       // the instance's expanded body (builder cache)

    const FieldValue* field(std::string_view field_name) const {
        for (const Field& f : fields)
            if (f.name == field_name) return &f.value;
        return nullptr;
    }
    FieldValue* field(std::string_view field_name) {
        for (Field& f : fields)
            if (f.name == field_name) return &f.value;
        return nullptr;
    }
};

struct InterfaceField {
    std::string name;
    FieldType type = FieldType::SFBool;
    bool is_event = false;  // eventIn / eventOut: no value
    FieldValue default_value;
};

struct ProtoDef {
    std::string name;
    SourceLocation location;
    std::vector<InterfaceField> interface;
    std::vector<NodePtr> body;  // the first node is what an instance becomes
    bool unresolved = false;    // an EXTERNPROTO we could not load: instances are skipped

    const InterfaceField* find(std::string_view field_name) const {
        for (const InterfaceField& f : interface)
            if (f.name == field_name) return &f;
        return nullptr;
    }
};

// What the parser knows about a built-in node type.
enum class NodeRole : uint8_t {
    Unknown,   // not a VRML97 node: warned about and skipped
    Used,      // parsed with its field table
    Ignored,   // standard but irrelevant to lighting (sensors, scripts, ...): skipped silently
    Unsupported,  // lines, points, text: skipped with one warning per kind
};

struct FieldSpec {
    std::string_view name;
    FieldType type;
};

struct NodeSpec {
    std::string_view type;
    NodeRole role;
    std::vector<FieldSpec> fields;
    const FieldSpec* find(std::string_view field_name) const {
        for (const FieldSpec& f : fields)
            if (f.name == field_name) return &f;
        return nullptr;
    }
};

// The built-in node's description, or nullptr for a name VRML97 does not define.
const NodeSpec* findNodeSpec(std::string_view type);

}  // namespace radbake::vrml
