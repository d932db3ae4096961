#include "pipeline/bake_options.h"

namespace radbake {

double texelToleranceFor(Quality quality) {
    switch (quality) {
        case Quality::Draft: return 0.05;
        case Quality::Medium: return 0.02;
        case Quality::High: return 0.01;
        case Quality::Reference: return 0.0;
    }
    return 0.0;
}

BakeOptions BakeOptions::forQuality(Quality quality) {
    BakeOptions options;
    options.solver = SolverOptions::forQuality(quality);
    options.readout = ReadoutOptions::forQuality(quality);
    options.lightmaps.texel_tolerance = texelToleranceFor(quality);
    return options;
}

std::string radbakeGenerator() { return std::string("radbake ") + RADBAKE_VERSION; }

}  // namespace radbake
