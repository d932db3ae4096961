#pragma once
// Mixed lighting (--realtime-lights): an emissive mesh the engine draws (Mesh::realtime_light)
// keeps its light in the solve, so its bounce stays, but no vertex, texel or probe holds its
// direct light. The read-out reads a source's radiosity B, so for its duration the mesh's
// elements carry B less their own emission; what they reflect stays.
#include <cstdint>
#include <vector>

#include "radiosity/solution.h"

namespace radbake {

// Takes the real-time meshes' own emission out of their elements' radiosity (and emission)
// while it lives, and puts it back when it goes.
class RealtimeEmissionLeftOut {
public:
    explicit RealtimeEmissionLeftOut(Solution& solution);
    ~RealtimeEmissionLeftOut();
    RealtimeEmissionLeftOut(const RealtimeEmissionLeftOut&) = delete;
    RealtimeEmissionLeftOut& operator=(const RealtimeEmissionLeftOut&) = delete;

private:
    Solution& solution_;
    std::vector<uint32_t> elements_;
    std::vector<DVec3> own_;  // per entry of elements_
};

}  // namespace radbake
