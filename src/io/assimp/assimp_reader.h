#pragma once
// Every format Assimp reads (OBJ/MTL, glTF, PLY, FBX, DAE, 3DS, ...). The only header of ours
// that fronts Assimp; assimp_reader.cpp is the only file that includes it.
#include <string>
#include <vector>

#include "core/memory.h"

#include "core/read_policy.h"
#include "scene/scene.h"

namespace radbake {

// What Assimp may open on the model's behalf (an OBJ's MTL, a glTF's buffers), and where to
// note what it did.
struct AssimpReads {
    const ReadPolicy* policy = nullptr;  // null: the model file's folder
    // When set, every file Assimp opened, and every one it tried to open and did not find.
    std::vector<std::string>* files_read = nullptr;
    std::vector<std::string>* files_refused = nullptr;  // when set, every path the policy refused
    // When set, the bake's memory budget: the read and the scene it yields are asked for first.
    MemoryGauge* memory = nullptr;
};

// Appends the file's meshes, materials, lights and cameras to `scene`. False after reporting
// at least one located error. A file the policy refuses is one warning naming it, and Assimp
// sees it as missing (never its bytes).
bool readWithAssimp(const std::string& path, Scene& scene, Diagnostics& diagnostics, const AssimpReads& reads = {});

}  // namespace radbake
