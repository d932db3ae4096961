// libFuzzer target for binary PLY: arbitrary bytes as input.ply through importScene
// (Assimp's PLY importer, our conversion and triangulation, validation). Seeds: corpus_ply/.
#include "fuzz_assimp_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return radbake::fuzz::importBytes(data, size, ".ply");
}
