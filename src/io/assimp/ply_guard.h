#pragma once
// A check before Assimp sees a PLY file, for inputs that make Assimp 5.2.5 misbehave
// (docs/fuzzing.md). Internal to the Assimp reader.
#include <string>

#include "core/diagnostics.h"

namespace radbake {

// True when `path` does not start with the PLY magic, or its header ends where Assimp's PLY
// importer can find the end. Otherwise reports a located error and returns false.
bool checkPlyInput(const std::string& path, Diagnostics& diagnostics);

}  // namespace radbake
