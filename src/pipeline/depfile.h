#pragma once
// A Make-syntax depfile (as `gcc -MD` writes and Ninja's `depfile =` reads): the bake's
// outputs, a colon, and every input it read, so a content build re-bakes when an Inline'd
// file, an MTL or the probes file changes.
#include <filesystem>
#include <string>
#include <vector>

#include "core/diagnostics.h"

namespace radbake {

// "target1 target2: input1 input2\n", each path escaped for Make (spaces, '#', '$').
std::string formatDepfile(const std::vector<std::string>& targets, const std::vector<std::string>& inputs);

// Writes it to `path` whole or not at all (a temporary file renamed into place), replacing
// only a regular file: a directory, FIFO or device there is an error and is kept.
bool writeDepfile(const std::filesystem::path& path, const std::vector<std::string>& targets,
                  const std::vector<std::string>& inputs, Diagnostics& diagnostics);

}  // namespace radbake
