#pragma once
// A check before Assimp sees an OBJ file, for inputs that make Assimp 5.2.5's OBJ importer
// leak (docs/fuzzing.md, findings 3 and 10). Internal to the Assimp reader.
#include <cstddef>
#include <string>

#include "core/diagnostics.h"

namespace radbake {

// Reads `path` as Assimp's OBJ parser does (its lines, continuations, cstype sections,
// vertex statements and face indices) and reports a located error, returning false, when a
// face, line or point statement names a vertex the file does not define, a line statement
// has a single vertex, or a statement is one Assimp would read past its line (an index with
// more than three parts, a vertical tab, an index beyond int, a stray backslash in a vertex).
// Files Assimp's own parser refuses (a face index that is not a number) pass: it fails them
// cleanly, and so do files larger than `max_bytes` (the reader refuses them).
bool checkObjInput(const std::string& path, size_t max_bytes, Diagnostics& diagnostics);

}  // namespace radbake
