#pragma once
// A check before Assimp sees a PLY file, for inputs that make Assimp 5.2.5 misbehave
// (docs/fuzzing.md). Internal to the Assimp reader.
#include <cstddef>
#include <string>

#include "core/diagnostics.h"

namespace radbake {

// True when `path` is not PLY as Assimp's importer tells (its first line starts with `ply`),
// or is larger than `max_bytes` (the reader refuses it), or is a PLY file Assimp reads without
// harm. Otherwise reports a located error and returns false: a header without an end_header
// line Assimp finds, a second vertex element or a second face (or tristrips) element, triangle
// strips (Assimp reads them wrong), a face texcoord list without a vertex_indices list or a
// material opacity without a specular_power (Assimp reads one through the other), a list
// length that is a float, an element whose count (as Assimp reads it) cannot fit in the bytes
// after the header, binary data past the file's end, or ASCII data Assimp throws on, a list
// longer than its line or an instance without a line.
bool checkPlyInput(const std::string& path, size_t max_bytes, Diagnostics& diagnostics);

}  // namespace radbake
