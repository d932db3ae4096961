#include "bake/lightmap_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace radbake {
namespace {

std::string formatNumber(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g", value);
    return buffer;
}

}  // namespace

double defaultTexelsPerMetre(const Scene& scene) {
    DVec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const Mesh& mesh : scene.meshes)
        for (const Vec3& p : mesh.positions) {
            lo = glm::min(lo, DVec3(p));
            hi = glm::max(hi, DVec3(p));
        }
    const DVec3 size = hi - lo;
    const double largest = std::max({size.x, size.y, size.z});
    if (!(largest > 0.0) || !std::isfinite(largest)) return kDefaultTexelsPerMetre;
    return std::max(kDefaultTexelsPerMetre, kMinTexelsAcross / largest);
}

std::optional<LightmapCharts> chartLightmapsWithinBudget(const Scene& scene, LightmapOptions options,
                                                         const LightmapBudget& budget, Diagnostics& diagnostics) {
    const double per_unit = budget.metres_per_unit;
    const bool given = budget.texels_per_unit > 0.0;
    // The imported scene is in metres; the option counts texels per scene unit.
    const double default_density = defaultTexelsPerMetre(scene);
    options.texels_per_metre = given ? budget.texels_per_unit / per_unit : default_density;
    const SourceLocation where{scene.source_path, 0, 0};
    const double max_texels = static_cast<double>(budget.max_texels);
    // Charts are built only at a density whose texels are near the budget: the estimate costs
    // the same at any density, the charts of a 1e6 m floor at 16 texels/m would not fit memory.
    const double wanted_estimate = estimateLightmapTexels(scene, options);
    const auto overBudget = [&](double texels) {
        if (!given) return false;
        const double fits = budget.texels_per_unit * std::sqrt(max_texels / texels);
        char count[32];
        std::snprintf(count, sizeof count, "%.0f", texels);
        diagnostics.error(where, "lightmaps at --texel-density " + formatNumber(budget.texels_per_unit) + " need " +
                                     count + " texels, above --max-texels " + std::to_string(budget.max_texels) +
                                     ": give a density of about " + formatNumber(fits) +
                                     " or less, or raise --max-texels");
        return true;
    };
    constexpr double kBuildFactor = 4.0;  // the estimate is an upper bound: build when within 4x
    if (wanted_estimate > kBuildFactor * max_texels) {
        if (overBudget(wanted_estimate)) return std::nullopt;
        for (double estimate = wanted_estimate; estimate > kBuildFactor * max_texels;) {
            options.texels_per_metre *= std::sqrt(max_texels / estimate);
            estimate = estimateLightmapTexels(scene, options);
        }
    }
    LightmapCharts charts = chartLightmaps(scene, options);
    const size_t wanted = wanted_estimate > kBuildFactor * max_texels ? static_cast<size_t>(wanted_estimate) : charts.texels;
    if (charts.texels > budget.max_texels && overBudget(static_cast<double>(charts.texels))) return std::nullopt;
    // Texels grow with the square of the density; the minimum chart size keeps tiny charts
    // from shrinking, so step down until the charts fit (or the density cannot help).
    for (int step = 0; charts.texels > budget.max_texels && step < 8; ++step) {
        options.texels_per_metre *= 0.97 * std::sqrt(static_cast<double>(budget.max_texels) / charts.texels);
        charts = chartLightmaps(scene, options);
    }
    if (charts.texels > budget.max_texels) {
        diagnostics.error(where, "lightmaps need " + std::to_string(charts.texels) + " texels even at " +
                                     formatNumber(options.texels_per_metre * per_unit) +
                                     " texels per unit, above --max-texels " + std::to_string(budget.max_texels) +
                                     " (too many small charts): raise --max-texels or bake with --no-lightmaps");
        return std::nullopt;
    }
    if (charts.texels != wanted)
        diagnostics.warning(where, "lightmaps at the default " + formatNumber(default_density) +
                                       " texels per metre would need " + std::to_string(wanted) +
                                       " texels, above --max-texels " + std::to_string(budget.max_texels) +
                                       ": baked at " + formatNumber(options.texels_per_metre * per_unit) +
                                       " texels per unit instead (" + std::to_string(charts.texels) +
                                       " texels); --texel-density or --max-texels choose otherwise");
    return charts;
}

}  // namespace radbake
