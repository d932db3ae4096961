#pragma once
// Our own reader for VRML97 (classic encoding) and VRML 1.0, gzipped or not.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/memory.h"
#include "core/read_policy.h"
#include "scene/scene.h"
#include "scene/scene_budget.h"

namespace radbake {

struct VrmlOptions {
    bool strict = false;  // unknown nodes and fields are errors
    // When set, the path of every file loaded (loadText) or looked for and missing is
    // appended: the scene's inputs.
    std::vector<std::string>* files_read = nullptr;
    // What the scene may read (Inline, EXTERNPROTO; textures are checked by applyTextures);
    // null: readVrml confines reads to the scene file's folder.
    const ReadPolicy* policy = nullptr;
    // When set, every path the policy refused is appended.
    std::vector<std::string>* files_refused = nullptr;
    // The bake's memory budget: geometry is estimated and asked for before it is built (a
    // DEF/USE fan-out, an Extrusion, a primitive); past it, a located error. Null: unbounded.
    MemoryGauge* memory = nullptr;
};

// True when the bytes begin like a VRML file ("#VRML") or a gzip stream.
bool looksLikeVrml(std::string_view first_bytes);

// Reads the file (VRML97 or VRML 1.0, told apart by its header line) and appends its meshes,
// materials, lights and cameras to `scene`. False after reporting at least one located error.
bool readVrml(const std::string& path, const VrmlOptions& options, Scene& scene,
              Diagnostics& diagnostics);

namespace vrml {

// True when `text` (after any UTF-8 byte-order mark) starts with a header the VRML97 reader
// takes: "#VRML V2.0", or X3D classic's "#X3D V3" / "#X3D V4" (VRML97 syntax plus a few statements).
bool isVrml97Text(std::string_view text);

// Reads a file, gunzipping it when it starts with the gzip magic. Reports a located error
// (at `from`, e.g. the Inline that asked for it) and returns nullopt when it cannot. The
// path is appended to options.files_read when it is set.
std::optional<std::string> loadText(const std::string& path, const SourceLocation& from, const VrmlOptions& options,
                                    Diagnostics& diagnostics);

// True when the scene may read `path` under options.policy, or the file is missing (the
// caller reports that). Otherwise one located warning at `from` naming the path and why
// ("Inline 'x' refused: ..."), never anything the file holds; the path is noted refused.
bool mayRead(const std::string& path, const SourceLocation& from, const std::string& what, const VrmlOptions& options,
             Diagnostics& diagnostics);

// Notes a file looked for and not found as an input (options.files_read), so adding it rebuilds.
void noteMissing(const std::string& path, const VrmlOptions& options);

// Resolves a relative URL against the directory of `base_file`; falls back to a
// case-insensitive match of each path component when the exact name does not exist.
// Returns nullopt for URLs that are not local files (http:, urn:, ...).
std::optional<std::string> resolveUrl(const std::string& base_file, const std::string& url);

// Reads one file's text as VRML97 or VRML 1.0, as its header line says, appending to `scene`
// in this file's own coordinates. `inline_stack` holds the files being read (recursion guard).
// An Inline/WWWInline reader calls this and then transforms what was appended (meshes, lights,
// cameras from the sizes it noted before) by its current matrix.
bool readText(std::string_view text, const std::string& path, const VrmlOptions& options,
              std::vector<std::string>& inline_stack, Scene& scene, Diagnostics& diagnostics);

// Limits `light` to the meshes first_mesh .. end_mesh - 1: the ones a VRML grouping node
// (VRML97 DirectionalLight) or Separator (VRML 1.0 light) holds.
void scopeLight(Light& light, size_t first_mesh, size_t end_mesh);

}  // namespace vrml
}  // namespace radbake
