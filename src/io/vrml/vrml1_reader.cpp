// TEMPORARY skeleton stub: replaced by the VRML 1.0 reader.
#include "io/vrml/vrml1_reader.h"

namespace radbake::vrml {
bool readVrml1(std::string_view, const std::string& path, const VrmlOptions&, std::vector<std::string>&, Scene&,
               Diagnostics& diagnostics) {
    diagnostics.error({path, 1, 1}, "VRML 1.0 reading is not built yet");
    return false;
}
}  // namespace radbake::vrml
