#pragma once
// Validators shared by every command's options: a value the command cannot use (NaN, an
// infinity, an empty string, a number out of the option's range) is a bad command line (exit
// 2, the option named by CLI11) before any work starts, never a silent default.
#include <CLI/CLI.hpp>

#include <limits>

#include "io/import.h"
#include "pipeline/bake_options.h"

namespace radbake::cli {

inline constexpr double kNoUpperBound = std::numeric_limits<double>::infinity();

// A finite real number in [low, high], or (low, high] when `low_open`; with kNoUpperBound
// any finite value above low. Ranges print readably: "in (0, 1]", "> 0", "in [0, 1e6]".
CLI::Validator realIn(double low, double high, bool low_open = false);
inline CLI::Validator positiveReal(double high = kNoUpperBound) { return realIn(0.0, high, true); }
inline CLI::Validator nonNegativeReal(double high = kNoUpperBound) { return realIn(0.0, high); }

// A whole decimal number in [low, high], attached with transform() (check() would keep the
// text as given): the value is handed on in plain decimal, as CLI11 reads "010" as octal.
CLI::Validator wholeIn(long long low, long long high);

// A path: an empty string is refused rather than taken for "not given".
CLI::Validator nonEmptyPath();

// --unit-scale and --emission-scale, as `bake` and `info` both read a scene.
void addSceneScaleOptions(CLI::App& command, ImportOptions& import);

// --sky, --sky-radiance, --up, --sun, --sun-irradiance, --sun-diameter: daylight the scene file
// does not hold (scene/daylight.h).
void addDaylightOptions(CLI::App& command, DaylightOptions& daylight);

// --read-root DIR (repeatable): a folder the scene may read files under besides its own.
void addReadRootOption(CLI::App& command, ImportOptions& import);

// --max-memory MB: the one budget of the whole command (import, textures, validation, solve).
void addMaxMemoryOption(CLI::App& command, double& max_memory_mb);

// The options that shape a bake's lightmap layout besides the scale: --texel-density,
// --atlas-size, --padding, --max-texels and --lightmap-scales FILE (its path, read later).
// `bake` and the tools that rebuild a bake's layout (tools/texel_probes) take the same ones.
void addLightmapLayoutOptions(CLI::App& command, LightmapSettings& lightmaps, std::string& lightmap_scales);

}  // namespace radbake::cli
