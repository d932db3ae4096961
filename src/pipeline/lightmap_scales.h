#pragma once
// Per-object lightmap density (issue 14), as Unity's "Scale In Lightmap" or ericw-tools'
// `_lightmap_scale`: a side file given with --lightmap-scales maps mesh or material names to
// a factor on the texel density,
//     # name          scale
//     Floor           0.5      (a mesh name: half the texels per metre, a quarter of the texels)
//     Gold frame      4        (the name is everything before the last word)
// A mesh takes the scale of a line naming it, else of a line naming its material, else 1.
// A side file rather than VRML metadata or glTF extras: it works for every format radbake
// reads and needs no edit of the asset (often someone else's). The scales apply within the
// texel budget (--max-texels): when the default density is lowered to fit, every mesh's
// density is lowered by the same factor, so their ratios stay.
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "scene/scene.h"

namespace radbake {

struct LightmapScaleRule {
    std::string name;  // a mesh name or a material name
    double scale = 1.0;
    SourceLocation location;
};

// The rules of `text` (the file's contents; `path` for messages). Errors, located at their
// line: a line without a scale, a scale that is not a positive finite number, a name given
// twice. nullopt after reporting.
std::optional<std::vector<LightmapScaleRule>> parseLightmapScales(const std::string& text, const std::string& path,
                                                                  Diagnostics& diagnostics);
std::optional<std::vector<LightmapScaleRule>> readLightmapScales(const std::string& path, Diagnostics& diagnostics);

// The scale of every mesh of `scene`, by mesh index. A rule that names no mesh and no
// material is a warning at its line (a typo would otherwise change nothing, silently).
std::vector<double> meshTexelScales(const Scene& scene, const std::vector<LightmapScaleRule>& rules,
                                    Diagnostics& diagnostics);

}  // namespace radbake
