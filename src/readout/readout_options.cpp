// The read-out presets of each Quality.
#include "readout/readout_options.h"

namespace radbake {

ReadoutOptions ReadoutOptions::forQuality(Quality quality) {
    ReadoutOptions o;
    switch (quality) {
        case Quality::Draft:
            o.probe_opening = 0.7;
            o.probe_samples = 2;
            o.probe_visibility_ratio = 0.03;
            o.probe_visibility_coarse = 0.2;
            o.edge_correction = EdgeCorrection::Shared;
            o.probe_grazing_corner_rays = false;
            o.probe_faint_share = 3e-2;
            o.sky = {8, 2};
            break;
        case Quality::Medium:
            break;  // the struct's defaults
        case Quality::High:
            o.probe_opening = 0.35;
            o.probe_samples = 3;
            o.probe_visibility_ratio = 0.005;
            o.probe_visibility_coarse = 0.07;
            o.probe_corner_rays = true;
            o.probe_coarse_opening = true;
            o.probe_faint_share = 1e-3;
            o.edge_correction = EdgeCorrection::On;
            o.sky = {16, 3};
            break;
        case Quality::Reference:
            o.probe_opening = 0.2;
            o.probe_samples = 4;
            o.probe_visibility_ratio = 0.002;
            o.probe_visibility_coarse = 0.05;
            o.probe_corner_rays = true;
            o.probe_coarse_opening = true;
            o.probe_faint_share = 0.0;
            o.edge_correction = EdgeCorrection::On;
            o.sky = {24, 4};
            break;
    }
    return o;
}

const char* toString(EdgeCorrection mode) {
    switch (mode) {
        case EdgeCorrection::Off: return "off";
        case EdgeCorrection::Shared: return "shared";
        case EdgeCorrection::On: return "on";
    }
    return "?";
}

}  // namespace radbake
