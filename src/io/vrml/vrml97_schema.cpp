// The VRML97 node types (ISO/IEC 14772-1 section 6) and the fields the reader parses.
#include <algorithm>
#include <array>
#include <unordered_map>

#include "io/vrml/vrml97_nodes.h"

namespace radbake::vrml {

bool parseFieldType(std::string_view name, FieldType& type) {
    static const std::unordered_map<std::string_view, FieldType> kTypes{
        {"SFBool", FieldType::SFBool},         {"SFInt32", FieldType::SFInt32},
        {"SFFloat", FieldType::SFFloat},       {"SFTime", FieldType::SFTime},
        {"SFVec2f", FieldType::SFVec2f},       {"SFVec3f", FieldType::SFVec3f},
        {"SFRotation", FieldType::SFRotation}, {"SFColor", FieldType::SFColor},
        {"SFString", FieldType::SFString},     {"SFImage", FieldType::SFImage},
        {"SFNode", FieldType::SFNode},         {"MFBool", FieldType::MFBool},
        {"MFInt32", FieldType::MFInt32},       {"MFFloat", FieldType::MFFloat},
        {"MFTime", FieldType::MFTime},         {"MFVec2f", FieldType::MFVec2f},
        {"MFVec3f", FieldType::MFVec3f},       {"MFRotation", FieldType::MFRotation},
        {"MFColor", FieldType::MFColor},       {"MFString", FieldType::MFString},
        {"MFNode", FieldType::MFNode},
    };
    const auto it = kTypes.find(name);
    if (it == kTypes.end()) return false;
    type = it->second;
    return true;
}

bool isMultiple(FieldType type) { return type >= FieldType::MFBool; }

int arity(FieldType type) {
    switch (type) {
        case FieldType::SFBool: case FieldType::MFBool:
        case FieldType::SFInt32: case FieldType::MFInt32:
        case FieldType::SFFloat: case FieldType::MFFloat:
        case FieldType::SFTime: case FieldType::MFTime: return 1;
        case FieldType::SFVec2f: case FieldType::MFVec2f: return 2;
        case FieldType::SFVec3f: case FieldType::MFVec3f:
        case FieldType::SFColor: case FieldType::MFColor: return 3;
        case FieldType::SFRotation: case FieldType::MFRotation: return 4;
        default: return 0;
    }
}

bool isFloatType(FieldType type) {
    switch (type) {
        case FieldType::SFFloat: case FieldType::MFFloat:
        case FieldType::SFTime: case FieldType::MFTime:
        case FieldType::SFVec2f: case FieldType::MFVec2f:
        case FieldType::SFVec3f: case FieldType::MFVec3f:
        case FieldType::SFColor: case FieldType::MFColor:
        case FieldType::SFRotation: case FieldType::MFRotation: return true;
        default: return false;
    }
}

bool isNodeType(FieldType type) { return type == FieldType::SFNode || type == FieldType::MFNode; }

namespace {

using T = FieldType;
using R = NodeRole;

std::vector<FieldSpec> withBbox(std::vector<FieldSpec> fields) {
    fields.push_back({"bboxCenter", T::SFVec3f});
    fields.push_back({"bboxSize", T::SFVec3f});
    return fields;
}

const std::vector<NodeSpec>& nodeSpecs() {
    static const std::vector<NodeSpec> kSpecs = [] {
        std::vector<NodeSpec> specs{
            {"Anchor", R::Used, withBbox({{"children", T::MFNode}, {"description", T::SFString},
                                          {"parameter", T::MFString}, {"url", T::MFString}})},
            {"Appearance", R::Used, {{"material", T::SFNode}, {"texture", T::SFNode}, {"textureTransform", T::SFNode}}},
            {"Billboard", R::Used, withBbox({{"children", T::MFNode}, {"axisOfRotation", T::SFVec3f}})},
            {"Box", R::Used, {{"size", T::SFVec3f}}},
            {"Collision", R::Used, withBbox({{"children", T::MFNode}, {"collide", T::SFBool}, {"proxy", T::SFNode}})},
            {"Color", R::Used, {{"color", T::MFColor}}},
            {"Cone", R::Used, {{"bottomRadius", T::SFFloat}, {"height", T::SFFloat}, {"side", T::SFBool}, {"bottom", T::SFBool}}},
            {"Coordinate", R::Used, {{"point", T::MFVec3f}}},
            {"Cylinder", R::Used, {{"bottom", T::SFBool}, {"height", T::SFFloat}, {"radius", T::SFFloat},
                                   {"side", T::SFBool}, {"top", T::SFBool}}},
            {"DirectionalLight", R::Used, {{"ambientIntensity", T::SFFloat}, {"color", T::SFColor}, {"direction", T::SFVec3f},
                                           {"intensity", T::SFFloat}, {"on", T::SFBool}}},
            {"ElevationGrid", R::Used, {{"color", T::SFNode}, {"normal", T::SFNode}, {"texCoord", T::SFNode},
                                        {"height", T::MFFloat}, {"ccw", T::SFBool}, {"colorPerVertex", T::SFBool},
                                        {"creaseAngle", T::SFFloat}, {"normalPerVertex", T::SFBool}, {"solid", T::SFBool},
                                        {"xDimension", T::SFInt32}, {"xSpacing", T::SFFloat},
                                        {"zDimension", T::SFInt32}, {"zSpacing", T::SFFloat}}},
            {"Extrusion", R::Used, {{"beginCap", T::SFBool}, {"ccw", T::SFBool}, {"convex", T::SFBool},
                                    {"creaseAngle", T::SFFloat}, {"crossSection", T::MFVec2f}, {"endCap", T::SFBool},
                                    {"orientation", T::MFRotation}, {"scale", T::MFVec2f}, {"solid", T::SFBool},
                                    {"spine", T::MFVec3f}}},
            {"Group", R::Used, withBbox({{"children", T::MFNode}})},
            {"ImageTexture", R::Used, {{"url", T::MFString}, {"repeatS", T::SFBool}, {"repeatT", T::SFBool}}},
            {"IndexedFaceSet", R::Used, {{"color", T::SFNode}, {"coord", T::SFNode}, {"normal", T::SFNode},
                                         {"texCoord", T::SFNode}, {"ccw", T::SFBool}, {"colorIndex", T::MFInt32},
                                         {"colorPerVertex", T::SFBool}, {"convex", T::SFBool}, {"coordIndex", T::MFInt32},
                                         {"creaseAngle", T::SFFloat}, {"normalIndex", T::MFInt32},
                                         {"normalPerVertex", T::SFBool}, {"solid", T::SFBool},
                                         {"texCoordIndex", T::MFInt32}}},
            {"Inline", R::Used, withBbox({{"url", T::MFString}})},
            {"LOD", R::Used, {{"level", T::MFNode}, {"center", T::SFVec3f}, {"range", T::MFFloat}}},
            {"Material", R::Used, {{"ambientIntensity", T::SFFloat}, {"diffuseColor", T::SFColor},
                                   {"emissiveColor", T::SFColor}, {"shininess", T::SFFloat},
                                   {"specularColor", T::SFColor}, {"transparency", T::SFFloat}}},
            {"Normal", R::Used, {{"vector", T::MFVec3f}}},
            {"PointLight", R::Used, {{"ambientIntensity", T::SFFloat}, {"attenuation", T::SFVec3f}, {"color", T::SFColor},
                                     {"intensity", T::SFFloat}, {"location", T::SFVec3f}, {"on", T::SFBool},
                                     {"radius", T::SFFloat}}},
            {"Shape", R::Used, {{"appearance", T::SFNode}, {"geometry", T::SFNode}}},
            {"Sphere", R::Used, {{"radius", T::SFFloat}}},
            {"SpotLight", R::Used, {{"ambientIntensity", T::SFFloat}, {"attenuation", T::SFVec3f},
                                    {"beamWidth", T::SFFloat}, {"color", T::SFColor}, {"cutOffAngle", T::SFFloat},
                                    {"direction", T::SFVec3f}, {"intensity", T::SFFloat}, {"location", T::SFVec3f},
                                    {"on", T::SFBool}, {"radius", T::SFFloat}}},
            {"Switch", R::Used, {{"choice", T::MFNode}, {"whichChoice", T::SFInt32}}},
            {"TextureCoordinate", R::Used, {{"point", T::MFVec2f}}},
            {"Transform", R::Used, withBbox({{"center", T::SFVec3f}, {"children", T::MFNode}, {"rotation", T::SFRotation},
                                             {"scale", T::SFVec3f}, {"scaleOrientation", T::SFRotation},
                                             {"translation", T::SFVec3f}})},
            {"Viewpoint", R::Used, {{"fieldOfView", T::SFFloat}, {"jump", T::SFBool}, {"orientation", T::SFRotation},
                                    {"position", T::SFVec3f}, {"description", T::SFString}}},
            {"Background", R::Used, {{"groundAngle", T::MFFloat}, {"groundColor", T::MFColor},
                                     {"skyAngle", T::MFFloat}, {"skyColor", T::MFColor}, {"backUrl", T::MFString},
                                     {"bottomUrl", T::MFString}, {"frontUrl", T::MFString}, {"leftUrl", T::MFString},
                                     {"rightUrl", T::MFString}, {"topUrl", T::MFString}}},
            {"IndexedLineSet", R::Unsupported, {}},
            {"PointSet", R::Unsupported, {}},
            {"Text", R::Unsupported, {}},
        };
        for (std::string_view ignored :
             {"AudioClip", "ColorInterpolator", "CoordinateInterpolator", "CylinderSensor", "Fog",
              "FontStyle", "MovieTexture", "NavigationInfo", "NormalInterpolator", "OrientationInterpolator",
              "PixelTexture", "PlaneSensor", "PositionInterpolator", "ProximitySensor", "ScalarInterpolator",
              "Script", "Sound", "SphereSensor", "TextureTransform", "TimeSensor",
              "TouchSensor", "VisibilitySensor", "WorldInfo"})
            specs.push_back({ignored, R::Ignored, {}});
        std::sort(specs.begin(), specs.end(), [](const NodeSpec& a, const NodeSpec& b) { return a.type < b.type; });
        return specs;
    }();
    return kSpecs;
}

}  // namespace

const NodeSpec* findNodeSpec(std::string_view type) {
    const std::vector<NodeSpec>& specs = nodeSpecs();
    const auto it = std::lower_bound(specs.begin(), specs.end(), type,
                                     [](const NodeSpec& spec, std::string_view t) { return spec.type < t; });
    return it != specs.end() && it->type == type ? &*it : nullptr;
}

}  // namespace radbake::vrml
