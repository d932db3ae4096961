// libFuzzer target for the OBJ path: arbitrary bytes as input.obj through importScene
// (Assimp's OBJ importer, our conversion and triangulation, validation). Seeds: corpus_obj/,
// dictionary: obj.dict.
#include "fuzz_assimp_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return radbake::fuzz::importBytes(data, size, ".obj");
}
