// The presets of each Quality, and the names of the enums as the command line spells them.
#include "radiosity/solver_options.h"

namespace radbake {

SolverOptions SolverOptions::forQuality(Quality quality) {
    SolverOptions o;
    o.quality = quality;
    switch (quality) {
        case Quality::Draft:
            o.error_threshold = 1e-3;
            o.min_element_area = 1e-3;
            o.iteration_tolerance = 1e-3;
            o.max_iterations = 100;
            o.refine_rounds = 1;
            o.local_error_threshold = 0.0;  // one round: the local rule has no irradiance to read
            o.quadrature_order = 2;
            o.quadrature_near_ratio = 0.5;
            o.quadrature_max_depth = 1;
            o.visibility_samples = 2;
            o.sky = {8, 2};
            break;
        case Quality::Medium:
            break;  // the struct's defaults
        case Quality::High:
            o.error_threshold = 5e-5;
            o.min_element_area = 2.5e-5;
            o.iteration_tolerance = 1e-5;
            o.max_iterations = 400;
            o.refine_rounds = 3;
            o.local_error_threshold = 0.05;
            o.quadrature_order = 3;
            o.quadrature_near_ratio = 1.0;
            o.quadrature_max_depth = 3;
            o.visibility_samples = 4;
            o.sky = {16, 3};
            break;
        case Quality::Reference:
            o.error_threshold = 1e-5;
            o.min_element_area = 4e-6;
            o.iteration_tolerance = 1e-6;
            o.max_iterations = 1000;
            o.refine_rounds = 4;
            o.local_error_threshold = 0.03;
            o.quadrature_order = 4;
            o.quadrature_near_ratio = 1.5;
            o.quadrature_max_depth = 4;
            o.visibility_samples = 6;
            o.sky = {24, 3};
            break;
    }
    return o;
}

const char* toString(LinkVisibility mode) {
    switch (mode) {
        case LinkVisibility::Rays: return "rays";
        case LinkVisibility::Aabb: return "aabb";
        case LinkVisibility::Obb: return "obb";
        case LinkVisibility::Exact: return "exact";
    }
    return "?";
}

const char* toString(Quality quality) {
    switch (quality) {
        case Quality::Draft: return "draft";
        case Quality::Medium: return "medium";
        case Quality::High: return "high";
        case Quality::Reference: return "reference";
    }
    return "?";
}

Quality qualityNamed(const std::string& name, Quality fallback) {
    for (const Quality q : {Quality::Draft, Quality::Medium, Quality::High, Quality::Reference})
        if (name == toString(q)) return q;
    return fallback;
}

}  // namespace radbake
