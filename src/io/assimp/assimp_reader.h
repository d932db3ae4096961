#pragma once
// Every format Assimp reads (OBJ/MTL, glTF, PLY, FBX, DAE, 3DS, ...). The only header of ours
// that fronts Assimp; assimp_reader.cpp is the only file that includes it.
#include <string>
#include <vector>

#include "scene/scene.h"

namespace radbake {

// Appends the file's meshes, materials, lights and cameras to `scene`. False after reporting
// at least one located error. Every file Assimp opened is appended to `files_read` when given.
bool readWithAssimp(const std::string& path, Scene& scene, Diagnostics& diagnostics,
                    std::vector<std::string>* files_read = nullptr);

}  // namespace radbake
