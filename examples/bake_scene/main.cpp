// bake_scene SCENE OUTDIR: bakes SCENE with radbake's default options and writes the bake into
// OUTDIR, as `radbake bake SCENE -o OUTDIR` does, through the library's two calls.
#include <cstdio>

#include "radbake.h"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s SCENE OUTDIR\n", argv[0]);
        return 2;
    }
    radbake::Diagnostics diagnostics;
    diagnostics.sink = [](const radbake::Diagnostic& d) {
        if (d.severity != radbake::Severity::Note) std::fprintf(stderr, "%s\n", radbake::formatDiagnostic(d).c_str());
    };
    radbake::Progress progress;  // no terminal line; a host could setSink() and cancel()
    const radbake::Bake bake = radbake::bake(argv[1], radbake::BakeOptions{}, progress, diagnostics);
    if (!bake.ok() || !radbake::writeBake(bake, argv[2], diagnostics)) return 1;
    std::printf("%s: %zu links, %zu lightmap atlases -> %s\n", argv[1], bake.report.solve.links,
                bake.report.lightmaps.atlases, argv[2]);
    return 0;
}
