#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "io/vrml/vrml_reader.h"

namespace radbake::vrml {

// Parses VRML 1.0 text (header line included) read from `path` and appends its meshes (in
// world space of this file), materials, lights and cameras to `scene`. `inline_stack` holds
// the files being read, outermost first (the recursion guard for WWWInline).
bool readVrml1(std::string_view text, const std::string& path, const VrmlOptions& options,
               std::vector<std::string>& inline_stack, Scene& scene, Diagnostics& diagnostics);

}  // namespace radbake::vrml
