// libFuzzer target for the VRML readers: arbitrary bytes through vrml::readText (VRML97 and
// VRML 1.0 by header) and, for gzip-looking input, through readVrml from a file in the
// process's scratch folder. Reads (Inline, EXTERNPROTO) are confined to that folder, which
// holds nothing else. Seeds: corpus_vrml/; dictionary: vrml.dict.
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "core/read_policy.h"
#include "fuzz_scratch.h"
#include "io/vrml/vrml97_parser.h"
#include "io/vrml/vrml_reader.h"

namespace {

const radbake::ReadPolicy& scratchPolicy() {
    // A small cap: a gzip bomb would otherwise inflate to the default 1 GiB, past -rss_limit_mb.
    static const radbake::ReadPolicy policy =
        radbake::readPolicyFor(radbake::fuzz::scratchFolder() + "/input.wrl", {}, size_t(64) << 20);
    return policy;
}

}  // namespace

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
    options.policy = &scratchPolicy();
    const std::string path = radbake::fuzz::scratchFolder() + "/input.wrl";
    if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f && static_cast<unsigned char>(bytes[1]) == 0x8b) {
        {
            std::ofstream out(path, std::ios::binary | std::ios::trunc);
            out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        }
        radbake::readVrml(path, options, scene, diagnostics);
        std::remove(path.c_str());
        return 0;
    }
    std::vector<std::string> stack{path};
    radbake::vrml::readText(bytes, path, options, stack, scene, diagnostics);
    return 0;
}
