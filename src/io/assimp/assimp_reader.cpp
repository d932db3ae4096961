// TEMPORARY skeleton stub: replaced by the Assimp importer.
#include "io/assimp/assimp_reader.h"

namespace radbake {
bool readWithAssimp(const std::string& path, Scene&, Diagnostics& diagnostics) {
    diagnostics.error({path, 0, 0}, "Assimp import is not built yet");
    return false;
}
}  // namespace radbake
