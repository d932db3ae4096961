#include "bake/shadowmask.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <cstring>
#include <optional>
#include <set>
#include <span>

#include "bake/chart_texels.h"
#include "radiosity/punctual_lights.h"
#include "readout/gather.h"
#include "visibility/ray_caster.h"

namespace radbake {
namespace {

constexpr size_t kMaxMaskedLights = 64;  // one bit each in a texel's reach mask
// An emissive mesh is sampled at this many points spread over it by emitted power (16 x 16 on
// a quad): a texel's share is within about 1/32 of its closed form behind a straight edge.
constexpr int kEmitterSamples = 256;

struct EmitterSample {
    DVec3 point, normal;
};

// A real-time light as the mask sees it: a punctual light, or an emissive mesh's samples.
struct MaskedSource {
    std::string name;
    const Light* light = nullptr;
    std::vector<EmitterSample> samples;
};

struct AtlasMask {
    int width = 0, height = 0;
    std::vector<uint64_t> reach;              // per texel: bit k when real-time light k lights it
    std::vector<uint8_t> covered;             // per texel: its centre lies on the chart's geometry
    std::vector<std::vector<uint8_t>> seen;   // per real-time light, per texel: visible share x 255
};

// Nothing reached yet, every light seen whole, for `lights` lights.
std::vector<AtlasMask> emptyMasks(const LightmapLayout& layout, size_t lights) {
    std::vector<AtlasMask> atlases(layout.atlases.size());
    for (size_t a = 0; a < atlases.size(); ++a) {
        AtlasMask& atlas = atlases[a];
        atlas.width = layout.atlases[a].width;
        atlas.height = layout.atlases[a].height;
        const size_t texels = static_cast<size_t>(atlas.width) * static_cast<size_t>(atlas.height);
        atlas.reach.assign(texels, 0);
        atlas.covered.assign(texels, 0);
        atlas.seen.assign(lights, std::vector<uint8_t>(texels, 255));
    }
    return atlases;
}

// `count` points spread over the root elements of `meshes` in proportion to their emitted
// power (systematic sampling of the roots, stratified within each).
std::vector<EmitterSample> emitterSamples(const Solution& solution, const std::vector<uint32_t>& meshes, int count) {
    const Scene& scene = *solution.scene;
    std::vector<uint32_t> roots;
    std::vector<double> power;
    double total = 0.0;
    for (uint32_t r = 0; r < solution.root_count; ++r) {
        const Element& e = solution.elements[r];
        if (std::find(meshes.begin(), meshes.end(), e.mesh) == meshes.end()) continue;
        const Vec3 own = polygonEmission(scene, scene.meshes[e.mesh], e.polygon);
        const double p = e.area * std::max({own.x, own.y, own.z});
        if (!(p > 0.0)) continue;
        roots.push_back(r);
        power.push_back(p);
        total += p;
    }
    std::vector<EmitterSample> samples;
    double before = 0.0;
    for (size_t k = 0; k < roots.size(); ++k) {
        const auto start = std::lround(count * before / total);
        before += power[k];
        const auto taken = std::lround(count * before / total) - start;
        if (taken <= 0) continue;
        const Element& e = solution.elements[roots[k]];
        const std::span<const DVec3> polygon(solution.vertices.data() + e.first_vertex, e.vertex_count);
        const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(taken))));
        const std::vector<DVec3> points = stratifiedPolygonPoints(polygon, side);
        for (long j = 0; j < taken; ++j)
            samples.push_back({points[static_cast<size_t>((j + 0.5) * static_cast<double>(points.size()) / taken)], e.normal});
    }
    return samples;
}

std::vector<MaskedSource> maskedSources(const Solution& solution) {
    const Scene& scene = *solution.scene;
    std::vector<MaskedSource> sources;
    for (const Light& light : scene.lights)
        if (light.realtime && light.on) sources.push_back({light.name, &light, {}});
    std::map<std::string, std::vector<uint32_t>> meshes_of;
    std::vector<std::string> names;  // in scene order
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        const std::string& name = scene.meshes[m].realtime_light;
        if (name.empty()) continue;
        if (meshes_of[name].empty()) names.push_back(name);
        meshes_of[name].push_back(m);
    }
    for (const std::string& name : names) {
        MaskedSource source{name, nullptr, emitterSamples(solution, meshes_of[name], kEmitterSamples)};
        if (!source.samples.empty()) sources.push_back(std::move(source));
    }
    return sources;
}

// The point-to-point kernel cos cos / d^2 from `from` (normal `normal`) to an emitter sample.
double emitterKernel(const DVec3& from, const DVec3& normal, const EmitterSample& s) {
    const DVec3 d = s.point - from;
    const double d2 = glm::dot(d, d);
    if (!(d2 > 0.0)) return 0.0;
    const double c = glm::dot(normal, d), c_emitter = -glm::dot(s.normal, d);
    return c > 0.0 && c_emitter > 0.0 ? c * c_emitter / (d2 * d2) : 0.0;
}

// The visible share of an emissive mesh's light at `from`, -1 where none of it arrives. Every
// sample takes a ray: a few first rays that agree would miss a penumbra's thin lit or dark strip.
double emitterShare(const RayCaster& rays, const MaskedSource& source, const DVec3& from, const DVec3& normal) {
    std::vector<DVec3> points;
    std::vector<double> kernel;
    for (const EmitterSample& s : source.samples)
        if (const double k = emitterKernel(from, normal, s); k > 0.0) {
            points.push_back(s.point);
            kernel.push_back(k);
        }
    if (points.empty()) return -1.0;
    std::vector<float> through(points.size());
    rays.transmittanceFrom(from, points, through);
    double open = 0.0, lit = 0.0;
    for (size_t i = 0; i < points.size(); ++i) {
        open += kernel[i];
        lit += kernel[i] * static_cast<double>(through[i]);
    }
    return open > 0.0 ? lit / open : -1.0;
}

// Visibility of every real-time light at the covered texels of one chart.
void maskChart(const Solution& solution, const LightmapChart& chart, const std::vector<MaskedSource>& sources,
               AtlasMask& atlas) {
    for (int ty = chart.y; ty < chart.y + chart.height; ++ty)
        for (int tx = chart.x; tx < chart.x + chart.width; ++tx) {
            DVec2 centre;
            const ChartFace* face = faceAtTexel(chart, tx, ty, centre);
            if (!face) continue;
            const size_t i = static_cast<size_t>(ty) * static_cast<size_t>(atlas.width) + static_cast<size_t>(tx);
            atlas.covered[i] = 1;
            const DVec3 normal = face->normal_world;
            const DVec3 from = gather::punctualFrom(solution, chart.mesh, face->triangle, face->worldPoint(centre), normal);
            for (size_t k = 0; k < sources.size(); ++k) {
                double share = -1.0;
                if (const Light* light = sources[k].light) {
                    if (!light->lights(chart.mesh)) continue;
                    const DVec3 open = lightIrradiance(*light, nullptr, from, normal);
                    const double peak = std::max({open.x, open.y, open.z});
                    if (!(peak > 0.0)) continue;
                    const DVec3 lit = lightIrradiance(*light, solution.rays.get(), from, normal);
                    share = std::max({lit.x, lit.y, lit.z}) / peak;
                } else {
                    share = emitterShare(*solution.rays, sources[k], from, normal);
                    if (share < 0.0) continue;
                }
                atlas.seen[k][i] = static_cast<uint8_t>(std::lround(255.0 * std::clamp(share, 0.0, 1.0)));
                atlas.reach[i] |= uint64_t{1} << k;
            }
        }
}

}  // namespace

ShadowmaskRecords readShadowmaskRecords(const Solution& solution, const LightmapLayout& layout,
                                        std::span<const uint8_t> wanted, ParallelRunner& runner) {
    ShadowmaskRecords out;
    std::vector<MaskedSource> realtime = maskedSources(solution);
    for (const MaskedSource& source : realtime) out.names.push_back(source.name);
    if (realtime.empty()) return out;
    if (realtime.size() > kMaxMaskedLights) realtime.resize(kMaxMaskedLights);
    std::vector<AtlasMask> atlases = emptyMasks(layout, realtime.size());
    // Charts' rectangles are disjoint: each task writes its own texels.
    runner.forEach(layout.charts.size(), 1, [&](size_t c) {
        const LightmapChart& chart = layout.charts[c];
        if (chart.atlas >= 0 && chartWanted(wanted, c))
            maskChart(solution, chart, realtime, atlases[static_cast<size_t>(chart.atlas)]);
    });
    const uint32_t size = static_cast<uint32_t>(sizeof(uint64_t) + 1 + realtime.size());
    out.records = collectChartRecords(layout, wanted, size, [&](size_t a, size_t texel, uint8_t* record) {
        std::memcpy(record, &atlases[a].reach[texel], sizeof(uint64_t));
        record[sizeof(uint64_t)] = atlases[a].covered[texel];
        for (size_t k = 0; k < realtime.size(); ++k) record[sizeof(uint64_t) + 1 + k] = atlases[a].seen[k][texel];
    });
    return out;
}

Shadowmask bakeShadowmask(const Solution& solution, const LightmapLayout& layout, int padding, ParallelRunner& runner,
                          Diagnostics& diagnostics) {
    const ShadowmaskRecords all = readShadowmaskRecords(solution, layout, {}, runner);
    return *assembleShadowmask(layout, padding, std::span<const ShadowmaskRecords>(&all, 1),
                               solution.scene ? solution.scene->source_path : std::string(), diagnostics);
}

std::optional<Shadowmask> assembleShadowmask(const LightmapLayout& layout, int padding,
                                             std::span<const ShadowmaskRecords> parts, const std::string& scene_path,
                                             Diagnostics& diagnostics) {
    Shadowmask mask;
    if (parts.empty()) return std::nullopt;
    const std::vector<std::string>& names = parts.front().names;
    for (const std::string& name : names) mask.lights.push_back({name, -1});
    if (names.empty()) return mask;
    const size_t masked = std::min(names.size(), kMaxMaskedLights);
    mask.lights_without_channel += names.size() - masked;
    std::vector<AtlasMask> atlases = emptyMasks(layout, masked);
    std::vector<ChartRecords> records;
    for (const ShadowmaskRecords& part : parts) {
        if (part.names != names) return std::nullopt;
        records.push_back(part.records);
    }
    const uint32_t size = static_cast<uint32_t>(sizeof(uint64_t) + 1 + masked);
    const bool whole = spreadChartRecords(layout, records, size, [&](size_t a, size_t texel, const uint8_t* record) {
        std::memcpy(&atlases[a].reach[texel], record, sizeof(uint64_t));
        atlases[a].covered[texel] = record[sizeof(uint64_t)];
        for (size_t k = 0; k < masked; ++k) atlases[a].seen[k][texel] = record[sizeof(uint64_t) + 1 + k];
    });
    if (!whole) return std::nullopt;
    std::vector<ShadowmaskLight> realtime(mask.lights.begin(), mask.lights.begin() + static_cast<std::ptrdiff_t>(masked));

    // Lights that light a common texel conflict; each takes the first channel its coloured
    // neighbours leave free.
    std::set<uint64_t> overlaps;
    for (const AtlasMask& atlas : atlases)
        for (const uint64_t reach : atlas.reach) {
            if (std::popcount(reach) > 1) overlaps.insert(reach);
            mask.texels_over_channels += std::popcount(reach) > kShadowmaskChannels;
        }
    std::string left_out;
    for (size_t k = 0; k < realtime.size(); ++k) {
        bool taken[kShadowmaskChannels] = {};
        for (const uint64_t reach : overlaps)
            if (reach >> k & 1)
                for (size_t j = 0; j < k; ++j)
                    if ((reach >> j & 1) && mask.lights[j].channel >= 0) taken[mask.lights[j].channel] = true;
        const auto free = std::find(std::begin(taken), std::end(taken), false);
        if (free != std::end(taken)) {
            mask.lights[k].channel = static_cast<int>(free - std::begin(taken));
        } else {
            ++mask.lights_without_channel;
            left_out += (left_out.empty() ? "'" : ", '") + realtime[k].name + "'";
        }
    }
    if (mask.lights_without_channel > 0)
        diagnostics.warning({scene_path, 0, 0},
                            std::to_string(mask.lights_without_channel) + " real-time light(s) have no shadowmask channel (" +
                                left_out + "): more than " + std::to_string(kShadowmaskChannels) +
                                " overlap at " + std::to_string(mask.texels_over_channels) + " texels");

    for (size_t a = 0; a < atlases.size(); ++a) {
        AtlasMask& atlas = atlases[a];
        std::vector<uint8_t> image(atlas.reach.size() * 4, 255);
        for (size_t i = 0; i < atlas.reach.size(); ++i)
            for (size_t k = 0; k < realtime.size(); ++k)
                if ((atlas.reach[i] >> k & 1) && mask.lights[k].channel >= 0)
                    image[4 * i + static_cast<size_t>(mask.lights[k].channel)] = atlas.seen[k][i];
        for (const uint32_t c : layout.atlases[a].charts)
            dilateChartTexels(layout.charts[c], padding, atlas.width, atlas.height, atlas.covered,
                              [&](size_t to, size_t from) { std::copy_n(&image[4 * from], 4, &image[4 * to]); });
        mask.images.push_back(std::move(image));
        mask.widths.push_back(atlas.width);
        mask.heights.push_back(atlas.height);
    }
    return mask;
}

}  // namespace radbake
