// libFuzzer target for the VRML readers: arbitrary bytes through vrml::readText (VRML97 and
// VRML 1.0 by header) and, for gzip-looking input, through readVrml from a temporary file.
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

#include "io/vrml/vrml97_parser.h"
#include "io/vrml/vrml_reader.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // Keep each input's work small; the defaults are sized for real scenes.
    radbake::vrml::Vrml97Limits& limits = radbake::vrml::vrml97Limits();
    limits.max_node_visits = 200'000;
    limits.max_expanded_nodes = 50'000;
    limits.max_triangles = 2'000'000;
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    radbake::Scene scene;
    radbake::Diagnostics diagnostics;
    radbake::VrmlOptions options;
    options.strict = size > 0 && (data[size - 1] & 1);
    if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f && static_cast<unsigned char>(bytes[1]) == 0x8b) {
        const std::string path = "/tmp/fuzz_vrml_" + std::to_string(getpid()) + ".wrl.gz";
        {
            std::ofstream out(path, std::ios::binary);
            out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        }
        radbake::readVrml(path, options, scene, diagnostics);
        std::remove(path.c_str());
        return 0;
    }
    // Inlines resolve against a folder that does not exist.
    std::vector<std::string> stack{"/nonexistent-fuzz-dir/input.wrl"};
    radbake::vrml::readText(bytes, stack.front(), options, stack, scene, diagnostics);
    return 0;
}
