#pragma once
// A check before Assimp sees a glTF file, for inputs that make Assimp 5.2.5 misbehave
// (docs/fuzzing.md). Internal to the Assimp reader.
#include <cstddef>
#include <string>

#include "core/diagnostics.h"

namespace radbake {

// Array and object nesting deeper than this is refused: Assimp's JSON parser recurses once
// per level, so a deep file exhausts the stack; real glTF files nest a few levels.
inline constexpr int kMaxGltfNesting = 64;

// True when `path` is neither JSON (its first byte past blanks is '{' or '[') nor glb, or is
// glTF 2.0 nested at most kMaxGltfNesting deep, or is larger than `max_bytes` (the reader
// refuses it). Otherwise reports a located error and returns false: glTF 1.0 (text, or glb
// version 1), JSON without a top-level asset.version of 2.x before any syntax error, nesting
// too deep, or a data: URI with a header over 120 bytes or a byte of 0x80 or above after its
// comma.
bool checkGltfInput(const std::string& path, size_t max_bytes, Diagnostics& diagnostics);

}  // namespace radbake
