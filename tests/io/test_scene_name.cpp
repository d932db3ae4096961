// The scene's name, which every output file and the default output folder are called by.
#include <doctest/doctest.h>

#include "io/import.h"
#include "test_vrml97_support.h"

using namespace radbake;

TEST_CASE("the scene name is the file name without its format suffix, dots in the name kept") {
    const auto dir = vrml_test::tempDir("scene_name");
    const std::string vrml = "#VRML V2.0 utf8\nShape { geometry Box {} }\n";
    const std::pair<const char*, const char*> cases[] = {
        {"furnace_rho_0.99.wrl", "furnace_rho_0.99"},  // a regression: was "furnace_rho_0"
        {"room.wrl", "room"},
        {"room.v2.wrl.gz", "room.v2"},  // plain text under a .gz name: gzip is detected from the bytes
        {"plain.vrml", "plain"},
        {"box.obj", "box"},
    };
    for (const auto& entry : cases) {
        // Not a structured binding: clang 14 (the RADBAKE_FUZZ build) cannot capture one in CAPTURE.
        const char* file = entry.first;
        const char* name = entry.second;
        CAPTURE(file);
        const bool obj = std::string(file).ends_with(".obj");
        const std::string path = vrml_test::writeFile(dir / file, obj ? "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n" : vrml);
        Diagnostics diagnostics;
        const std::optional<Scene> scene = importScene(path, ImportOptions{}, diagnostics);
        REQUIRE(scene);
        CHECK(scene->name == name);
    }
}
