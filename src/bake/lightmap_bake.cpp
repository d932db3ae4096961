// Lightmap texel evaluation and dilation.
#include "bake/lightmap_bake.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>

#include "bake/lightmap_adaptive.h"
#include "bake/lightmap_seams.h"
#include "geometry/polygon.h"
#include "readout/reconstruct.h"
#include "radiosity/solution.h"
#include "visibility/ray_caster.h"

namespace radbake {
namespace {

DVec2 polygonCentroid(const std::vector<DVec2>& polygon) {
    double twice_area = 0.0;
    DVec2 sum(0.0);
    for (size_t k = 0; k < polygon.size(); ++k) {
        const DVec2& a = polygon[k];
        const DVec2& b = polygon[(k + 1) % polygon.size()];
        const double cross = a.x * b.y - a.y * b.x;
        twice_area += cross;
        sum += (a + b) * cross;
    }
    if (twice_area == 0.0) {  // degenerate sliver: the vertex average is still on it
        for (const DVec2& p : polygon) sum += p;
        return sum / static_cast<double>(polygon.size());
    }
    return sum / (3.0 * twice_area);
}

// Black, empty images of the layout's atlases.
std::vector<LightmapImage> emptyImages(const LightmapLayout& layout) {
    std::vector<LightmapImage> images;
    for (const LightmapAtlas& atlas : layout.atlases) {
        LightmapImage image;
        image.width = atlas.width;
        image.height = atlas.height;
        image.rgb.assign(static_cast<size_t>(atlas.width) * atlas.height * 3, 0.0f);
        image.state.assign(static_cast<size_t>(atlas.width) * atlas.height, TexelState::Empty);
        images.push_back(std::move(image));
    }
    return images;
}

size_t texelIndex(const LightmapImage& image, int x, int y) { return static_cast<size_t>(y) * image.width + x; }

// A ray meets the back of a surface: it travels along the hit triangle's front normal.
// (A two-sided surface's back is its back twin's front: closestHit names the twin.)
bool hitsBack(const Scene& scene, const RayCaster& rays, const DVec3& p, const DVec3& direction) {
    const std::optional<RayHit> hit = rays.closestHit(p, direction, 2.0 * rays.sceneExtent());
    if (!hit) return false;
    const Mesh& mesh = scene.meshes[hit->triangle.mesh];
    const UVec3& tri = mesh.triangles[hit->triangle.triangle];
    const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
    return dot(cross(b - a, c - a), direction) > 0.0;
}

}  // namespace

bool insideGeometry(const Scene& scene, const RayCaster& rays, const DVec3& p, const DVec3& normal) {
    if (!hitsBack(scene, rays, p, normal)) return false;
    DVec3 u, v;
    tangentFrame(normal, u, v);
    // The normal's ray and kHiddenRays - 1 more on a golden-angle spiral, uniform in cos(theta)
    // over (0, 1): fixed directions, so the answer is deterministic.
    for (int k = 1; k < kHiddenRays; ++k) {
        const double cos_theta = 1.0 - (k - 0.5) / (kHiddenRays - 1);
        const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
        const double phi = 2.39996322972865332 * k;
        const DVec3 direction = cos_theta * normal + sin_theta * (std::cos(phi) * u + std::sin(phi) * v);
        if (!hitsBack(scene, rays, p, direction)) return false;
    }
    return true;
}

bool texelSamplePoint(const LightmapChart& chart, int i, int j, DVec2& p_plane) {
    size_t face = 0;
    return texelSamplePoint(chart, i, j, p_plane, face);
}

bool texelSamplePoint(const LightmapChart& chart, int i, int j, DVec2& p_plane, size_t& face) {
    return texelCoverage(chart, i, j, p_plane, face) > 0.0;
}

double texelCoverage(const LightmapChart& chart, int i, int j, DVec2& p_plane, size_t& face) {
    const double size = 1.0 / chart.texels_per_metre;
    const DVec2 lo = chart.min_plane + DVec2(i, j) * size;
    const DVec2 hi = lo + DVec2(size);
    double best = 0.0, covered = 0.0;
    for (size_t f = 0; f < chart.faces.size(); ++f) {
        // Most of a big chart's faces are nowhere near the texel: a box test before the clip.
        const std::vector<DVec2>& loop = chart.faces[f].p_plane;
        DVec2 face_lo(std::numeric_limits<double>::max()), face_hi(-std::numeric_limits<double>::max());
        for (const DVec2& p : loop) face_lo = glm::min(face_lo, p), face_hi = glm::max(face_hi, p);
        if (face_lo.x > hi.x || face_lo.y > hi.y || face_hi.x < lo.x || face_hi.y < lo.y) continue;
        const std::vector<DVec2> piece = clipToRectangle(loop, lo, hi);
        if (piece.empty()) continue;
        const double area = polygonArea(piece);
        covered += std::max(area, 0.0);
        if (area > best) {
            best = area;
            p_plane = polygonCentroid(piece);
            face = f;
        }
    }
    if (!(best > 0.0)) return 0.0;
    return covered / ((hi.x - lo.x) * (hi.y - lo.y));
}

Lightmaps evaluateLightmaps(LightmapLayout layout, const IrradianceFunction& irradiance, int padding,
                            ParallelRunner& runner, double texel_tolerance, Progress* progress,
                            const HiddenTest& hidden, double dark) {
    Lightmaps lightmaps;
    lightmaps.layout = std::move(layout);
    lightmaps.images = emptyImages(lightmaps.layout);
    const AdaptiveCounts counts =
        evaluateTexelsAdaptive(lightmaps.layout, lightmaps.images, irradiance, texel_tolerance, runner, progress, hidden, dark);
    lightmaps.covered_texels = counts.covered;
    lightmaps.hidden_texels = counts.hidden;
    lightmaps.evaluated_texels = counts.evaluated;
    lightmaps.interpolated_texels = counts.interpolated;
    lightmaps.required_texels = counts.required;
    dilateLightmaps(lightmaps, padding);
    return lightmaps;
}

void dilateLightmaps(Lightmaps& lightmaps, int padding) {
    padding = std::max(padding, 0);
    for (const LightmapChart& chart : lightmaps.layout.charts) {
        if (chart.atlas < 0) continue;
        LightmapImage& image = lightmaps.images[chart.atlas];
        const int x0 = std::max(chart.x - padding, 0), y0 = std::max(chart.y - padding, 0);
        const int x1 = std::min(chart.x + chart.width + padding, image.width);
        const int y1 = std::min(chart.y + chart.height + padding, image.height);
        bool any_filled = false;
        for (int y = chart.y; y < chart.y + chart.height && !any_filled; ++y)
            for (int x = chart.x; x < chart.x + chart.width; ++x)
                if (image.state[texelIndex(image, x, y)] != TexelState::Empty) any_filled = true;
        if (!any_filled) continue;  // a chart with no covered texel stays black
        for (bool changed = true; changed;) {
            changed = false;
            std::vector<std::pair<size_t, DVec3>> fills;  // applied after the pass: a pass reads only older texels
            for (int y = y0; y < y1; ++y) {
                for (int x = x0; x < x1; ++x) {
                    if (image.state[texelIndex(image, x, y)] != TexelState::Empty) continue;
                    DVec3 sum(0.0);
                    int count = 0;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const int nx = x + dx, ny = y + dy;
                            if (nx < x0 || ny < y0 || nx >= x1 || ny >= y1) continue;
                            const size_t n = texelIndex(image, nx, ny);
                            if (image.state[n] == TexelState::Empty) continue;
                            sum += DVec3(image.rgb[3 * n], image.rgb[3 * n + 1], image.rgb[3 * n + 2]);
                            ++count;
                        }
                    if (count > 0) fills.emplace_back(texelIndex(image, x, y), sum / static_cast<double>(count));
                }
            }
            for (const auto& [at, value] : fills) {
                for (int c = 0; c < 3; ++c) image.rgb[3 * at + c] = static_cast<float>(value[c]);
                image.state[at] = TexelState::Dilated;
            }
            changed = !fills.empty();
        }
    }
}

double brightestLight(const Solution& solution) {
    const Scene* scene = solution.scene;
    double brightest = 0.0;
    for (const Element& e : solution.elements) {
        if (!e.isLeaf()) continue;
        DVec3 h(0.0);
        for (uint32_t a = static_cast<uint32_t>(&e - solution.elements.data()); a != kNoElement; a = solution.elements[a].parent)
            h += solution.elements[a].gathered;
        // The solve holds punctual and sky light as reflected emission: rho x H on top of the
        // element's own (taken out already for a real-time mesh).
        const Mesh* mesh = scene && e.mesh < scene->meshes.size() ? &scene->meshes[e.mesh] : nullptr;
        const DVec3 own = mesh && mesh->realtime_light.empty() ? kPi * DVec3(polygonEmission(*scene, *mesh, e.polygon)) : DVec3(0.0);
        for (int c = 0; c < 3; ++c)
            if (e.reflectance[c] > 0.0) h[c] += std::max(0.0, e.emission[c] - own[c]) / e.reflectance[c];
        brightest = std::max({brightest, h.x, h.y, h.z});
    }
    return brightest / kPi;
}

LightmapCharts chartLightmaps(const Scene& scene, const LightmapOptions& options) {
    LightmapCharts out;
    out.options = options;
    out.charts = buildLightmapCharts(scene, options);
    for (const LightmapChart& chart : out.charts)
        out.texels += static_cast<size_t>(chart.width) * static_cast<size_t>(chart.height);
    return out;
}

LightmapPart readLightmapPart(const Scene& scene, const Solution& solution, const ReadoutOptions& readout,
                              const LightmapLayout& layout, const LightmapOptions& options,
                              std::span<const uint8_t> wanted, ParallelRunner& runner, Progress* progress) {
    std::optional<LinkReconstruction> links;
    // A scene without light reads 0 everywhere: no gather, and no hidden texel to fill.
    const bool lit = carriesLight(solution);
    if (lit && readout.gather == GatherMode::Links) links.emplace(solution, readout, runner);
    const IrradianceFunction irradiance = [&](const SurfacePoint& at) {
        if (!lit) return DVec3(0.0);
        return links ? links->irradiance(at.mesh, at.triangle, at.p_world, at.normal_world,
                                         LinkReconstruction::Reading::Texel)
                     : surfaceIrradiance(solution, readout, at.p_world, at.normal_world, at.mesh, at.triangle);
    };
    const HiddenTest hidden = [&](const SurfacePoint& at) {
        return lit && solution.rays && insideGeometry(scene, *solution.rays, at.p_world, at.normal_world);
    };
    const double dark = kDarkFloor * brightestLight(solution);
    std::vector<LightmapImage> images = emptyImages(layout);
    LightmapPart part;
    const AdaptiveCounts counts = evaluateTexelsAdaptive(layout, images, irradiance, options.texel_tolerance, runner,
                                                         progress, hidden, dark, wanted);
    part.covered = counts.covered;
    part.hidden = counts.hidden;
    part.evaluated = counts.evaluated;
    part.interpolated = counts.interpolated;
    part.required = counts.required;
    if (runner.cancelled()) return part;
    for (uint32_t c = 0; c < layout.charts.size(); ++c) {
        const LightmapChart& chart = layout.charts[c];
        if (chart.atlas < 0 || !(wanted.empty() || (c < wanted.size() && wanted[c]))) continue;
        part.charts.push_back(c);
        const LightmapImage& image = images[static_cast<size_t>(chart.atlas)];
        for (int y = chart.y; y < chart.y + chart.height; ++y)
            for (int x = chart.x; x < chart.x + chart.width; ++x) {
                const size_t t = texelIndex(image, x, y);
                part.rgb.insert(part.rgb.end(), image.rgb.begin() + 3 * t, image.rgb.begin() + 3 * t + 3);
                part.state.push_back(image.state[t]);
            }
    }
    if (progress) progress->update(kTexelShare);
    if (options.stitch_seams && options.padding >= 1) {
        // What the texels' reads cost so far, and what the reads of points other charts own add.
        ReadoutWork others, before;
        const auto shared = [&](bool starting) {
            if (!links) return;
            if (starting) before = links->work();
            else others += links->work() - before;
        };
        const ChartEdges found = findChartEdges(scene, layout);
        const EdgeLight light = readChartEdges(found, irradiance, runner, options.texel_tolerance, dark, wanted, shared);
        for (size_t q = 0; q < light.read.size(); ++q)
            if (light.read[q]) {
                part.edge_queries.push_back(q);
                part.edge_light.push_back(light.light[q]);
            }
        part.edge_evaluations = light.evaluations;
        if (links) part.work = links->work() - others;
    } else if (links) {
        part.work = links->work();
    }
    if (progress) progress->update(1.0);
    return part;
}

bool assembleLightmaps(const Scene& scene, LightmapLayout layout, const LightmapOptions& options,
                       std::span<const LightmapPart> parts, ParallelRunner& runner, Lightmaps& lightmaps) {
    lightmaps = Lightmaps{};
    lightmaps.layout = std::move(layout);
    const LightmapLayout& placed = lightmaps.layout;
    lightmaps.images = emptyImages(placed);
    std::vector<uint8_t> filled(placed.charts.size(), 0);
    for (const LightmapPart& part : parts) {
        size_t at = 0;
        for (const uint32_t c : part.charts) {
            if (c >= placed.charts.size() || filled[c] || placed.charts[c].atlas < 0) return false;
            filled[c] = 1;
            const LightmapChart& chart = placed.charts[c];
            LightmapImage& image = lightmaps.images[static_cast<size_t>(chart.atlas)];
            if (at + static_cast<size_t>(chart.width) * chart.height > part.state.size()) return false;
            for (int y = chart.y; y < chart.y + chart.height; ++y)
                for (int x = chart.x; x < chart.x + chart.width; ++x, ++at) {
                    const size_t t = texelIndex(image, x, y);
                    std::copy_n(part.rgb.begin() + 3 * at, 3, image.rgb.begin() + 3 * t);
                    image.state[t] = part.state[at];
                }
        }
        if (at != part.state.size() || part.rgb.size() != 3 * at) return false;
        lightmaps.covered_texels += part.covered;
        lightmaps.hidden_texels += part.hidden;
        lightmaps.evaluated_texels += part.evaluated;
        lightmaps.interpolated_texels += part.interpolated;
        lightmaps.required_texels += part.required;
        lightmaps.work += part.work;
    }
    for (size_t c = 0; c < placed.charts.size(); ++c)
        if (placed.charts[c].atlas >= 0 && !filled[c]) return false;
    dilateLightmaps(lightmaps, options.padding);
    if (!options.stitch_seams || options.padding < 1) return true;
    const ChartEdges found = findChartEdges(scene, placed);
    EdgeLight light;
    light.light.assign(found.edges.size() + 2 * found.seams.size(), DVec3(0.0));
    light.read.assign(light.light.size(), 0);
    for (const LightmapPart& part : parts) {
        if (part.edge_queries.size() != part.edge_light.size()) return false;
        for (size_t k = 0; k < part.edge_queries.size(); ++k) {
            const uint64_t q = part.edge_queries[k];
            if (q >= light.read.size() || light.read[q]) return false;
            light.read[q] = 1;
            light.light[q] = part.edge_light[k];
        }
        light.evaluations += part.edge_evaluations;
    }
    if (std::find(light.read.begin(), light.read.end(), 0) != light.read.end()) return false;
    fitChartEdges(lightmaps, found, light, runner);
    return true;
}

bool bakeLightmaps(const Scene& scene, const Solution& solution, const ReadoutOptions& readout, LightmapCharts charts,
                   ParallelRunner& runner, Lightmaps& lightmaps, Diagnostics& diagnostics, Progress* progress) {
    const LightmapOptions& options = charts.options;
    LightmapLayout layout;
    if (!packLightmapCharts(std::move(charts.charts), options, layout, diagnostics)) return false;
    const LightmapPart all = readLightmapPart(scene, solution, readout, layout, options, {}, runner, progress);
    if (runner.cancelled()) return false;
    return assembleLightmaps(scene, std::move(layout), options, std::span<const LightmapPart>(&all, 1), runner, lightmaps) &&
           !runner.cancelled();
}

}  // namespace radbake
