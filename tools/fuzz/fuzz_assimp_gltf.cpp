// libFuzzer target for glTF: arbitrary bytes through importScene (Assimp's glTF 2.0 and 1.0
// importers, our conversion and triangulation, validation). Assimp picks the text or binary
// reader by extension, so input starting with the glb magic is written as input.glb, any
// other as input.gltf. Seeds: corpus_gltf/ (data: URI buffers); dictionary: gltf.dict.
#include <cstring>

#include "fuzz_assimp_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    return radbake::fuzz::importBytes(data, size, binary ? ".glb" : ".gltf");
}
