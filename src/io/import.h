#pragma once
// The import stage: any supported scene file -> one validated Scene.
#include <optional>
#include <string>
#include <vector>

#include "core/read_policy.h"
#include "scene/daylight.h"
#include "scene/scene.h"

namespace radbake {

struct ImportOptions {
    float unit_scale = 1.0f;      // scene units -> metres
    float emission_scale = 1.0f;  // multiplies every emitted radiance
    // A sky and a sun the file does not hold (--sky, --sun, ...): added to the scene after the
    // scales, so --emission-scale does not touch them.
    DaylightOptions daylight;
    bool strict = false;          // unknown nodes and fields are errors, not warnings
    // Folders the scene may read files under besides its own (--read-root): an Inline, a
    // texture, an MTL or a glTF buffer anywhere else is refused with a warning, as missing.
    std::vector<std::string> read_roots;
    size_t max_input_bytes = kDefaultMaxInputBytes;  // each file read, each gzip stream inflated
    // --max-memory (MiB; 0: 3/4 of the machine's memory): geometry a scene expands to (DEF/USE
    // fan-out, Extrusion, primitives), each texture and validation are estimated against it
    // before they are built. bake() reads the scene under SolverOptions::max_memory_mb when
    // this is 0, so one budget covers the whole bake.
    double max_memory_mb = 0.0;
};

// Reads VRML97 / VRML 1.0 with our own reader (also gzipped) and everything else through
// Assimp, then validates and splits vertices at hard edges (scene/creases.h; counted in
// Scene::crease_split). Files the scene names are read under core/read_policy.h's policy
// (Scene::refused_inputs). Returns nullopt after reporting at least one located error: no
// exception leaves it (an allocation that fails anyway is a located error naming the phase).
std::optional<Scene> importScene(const std::string& path, const ImportOptions& options,
                                 Diagnostics& diagnostics);

}  // namespace radbake
