#pragma once
// A bake's radiosity solution saved to a file and reused by a later bake of the same scene
// with the same solver settings (issue 12): a technical artist tuning lightmap density,
// atlas size, padding, vertex or probe settings pays only for the texels.
//
// The key is a SHA-256 of what the solve depends on: the scene as imported (geometry,
// per-polygon reflectance and emission, lights; so --unit-scale, --emission-scale, an edited
// texture or Inline'd file all change it), every solver knob but the memory budget (never the
// read-out's: --edge-correction, the texel settings), and the
// radbake version and record sizes. A file whose key differs is not read (the bake solves and
// overwrites it). The ray caster is rebuilt from the scene on load.
#include <filesystem>
#include <optional>
#include <string>

#include "core/diagnostics.h"
#include "core/ranks.h"
#include "radiosity/solution.h"
#include "scene/scene.h"

namespace radbake {

std::string solutionKey(const Scene& scene, const SolverOptions& options);

// Writes the solution (to a temporary name, then renamed over a regular file or nothing).
// False after a warning: a cache that cannot be written does not fail the bake.
bool saveSolution(const Solution& solution, const std::string& key, const std::filesystem::path& file,
                  Diagnostics& diagnostics);

// Whether `file` is a regular file holding a solution saved under `key` (its header only is read).
bool solutionFileHolds(const std::string& key, const std::filesystem::path& file);

// The solution saved under `key` in `file`, for `scene` (which it then points to); nullopt
// when the file is absent, holds another key or cannot be read (a note says why), or is not
// a regular file (a directory, FIFO, device: an error, as the bake would replace it). With
// ranks, the lead reads the file and sends it to the others (collective).
std::optional<Solution> loadSolution(const Scene& scene, const SolverOptions& options, const std::string& key,
                                     const std::filesystem::path& file, int threads, Diagnostics& diagnostics,
                                     const Ranks& ranks = Ranks::one());

}  // namespace radbake
