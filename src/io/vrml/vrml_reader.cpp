// TEMPORARY skeleton stub: replaced by the VRML reader.
#include "io/vrml/vrml_reader.h"

namespace radbake {
bool looksLikeVrml(std::string_view first_bytes) { return first_bytes.starts_with("#VRML"); }
bool readVrml(const std::string& path, const VrmlOptions&, Scene&, Diagnostics& diagnostics) {
    diagnostics.error({path, 1, 1}, "VRML reading is not built yet");
    return false;
}
}  // namespace radbake
