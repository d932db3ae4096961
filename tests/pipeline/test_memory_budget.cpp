// The library's side of the memory budget (issue 32): bake() and importScene() refuse a scene
// that expands past BakeOptions' (ImportOptions') budget with a located error, and throw nothing.
#include <doctest/doctest.h>

#include <fstream>
#include <string>

#include "radbake.h"
#include "../export/temp_files.h"

using namespace radbake;
using testfs::TempDir;

namespace {

// A Sphere DEF'd once, then `levels` Groups each USing the previous one twice.
void writeFanOut(const std::filesystem::path& path, int levels) {
    std::ofstream out(path);
    out << "#VRML V2.0 utf8\n"
           "DEF L0 Shape { appearance Appearance { material Material { emissiveColor 1 1 1 } } geometry Sphere {} }\n";
    for (int k = 1; k <= levels; ++k)
        out << "DEF L" << k << " Group { children [ USE L" << k - 1 << " USE L" << k - 1 << " ] }\n";
    REQUIRE(out.good());
}

// The one error: located on a line of `path`, naming --max-memory.
void checkBudgetError(const Diagnostics& diagnostics, const std::string& path) {
    REQUIRE(diagnostics.errorCount() == 1);
    for (const Diagnostic& d : diagnostics.all()) {
        if (d.severity != Severity::Error) continue;
        INFO(d.message);
        CHECK(d.location.file == path);
        CHECK(d.location.line > 0);
        CHECK(d.message.find("--max-memory") != std::string::npos);
    }
}

}  // namespace

TEST_CASE("bake(): a DEF/USE fan-out past the bake's budget is a located error at import, nothing thrown") {
    TempDir dir;
    const std::string path = (dir.path / "fan.wrl").string();
    writeFanOut(dir.path / "fan.wrl", 30);
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.solver.max_memory_mb = 512;  // one budget: bake() imports under it too
    Progress progress(false);
    Diagnostics diagnostics;
    const Bake baked = bake(path, options, progress, diagnostics);  // a throw fails the test
    CHECK((baked.status == BakeStatus::InputError));
    checkBudgetError(diagnostics, path);
}

TEST_CASE("importScene(): ImportOptions::max_memory_mb bounds the geometry a scene expands to") {
    TempDir dir;
    const std::string path = (dir.path / "fan.wrl").string();
    writeFanOut(dir.path / "fan.wrl", 12);  // 4096 spheres: about 0.9 GiB estimated
    ImportOptions options;
    options.max_memory_mb = 512;
    Diagnostics refused;
    CHECK_FALSE(importScene(path, options, refused).has_value());
    checkBudgetError(refused, path);
    // The same file within a budget that holds it.
    writeFanOut(dir.path / "fan.wrl", 4);
    Diagnostics fits;
    CHECK(importScene(path, options, fits).has_value());
    CHECK_FALSE(fits.hasErrors());
}
