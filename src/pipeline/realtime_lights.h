#pragma once
// Mixed lighting (issue 33): --realtime-lights FILE names, one a line, the lights (punctual
// lights and emissive meshes) whose direct light the engine draws in real time (as Unity's
// Mixed lights, Godot's Dynamic bake mode).
// Their light still bounces through the solve, but no vertex, texel or probe holds their
// direct light, and the lightmaps get a shadowmask: each such light's visible share per texel
// (bake/shadowmask.h).
//     # lights the engine draws
//     Lamp_1
//     sun                 (the --sun light; an environment map's suns are "map sun 1", ...)
// A light is named by its VRML97 DEF name or its Assimp node name; an emissive mesh by its
// mesh's name (VRML97: the geometry node's DEF name; Assimp: the mesh's).
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "scene/scene.h"

namespace radbake {

struct RealtimeLightName {
    std::string name;
    SourceLocation location;
};

// The names of `text` (the file's contents; `path` for messages), '#' starting a comment.
// A name given twice is an error at its line; nullopt after reporting.
std::optional<std::vector<RealtimeLightName>> parseRealtimeLights(const std::string& text, const std::string& path,
                                                                  Diagnostics& diagnostics);
std::optional<std::vector<RealtimeLightName>> readRealtimeLights(const std::string& path, Diagnostics& diagnostics);

// Marks every light of `scene` a name gives as Light::realtime, and every emissive mesh it
// names (Mesh::realtime_light). A name that is neither is an error at its line, naming the
// lights there are. False after reporting.
bool markRealtimeLights(Scene& scene, const std::vector<RealtimeLightName>& names, Diagnostics& diagnostics);

}  // namespace radbake
