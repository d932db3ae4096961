#pragma once
// The shadowmask of mixed lighting (issue 33, --realtime-lights): for each light whose direct
// light the engine draws, its visible share at each lightmap texel (the shadowed over the
// unshadowed direct light: 0 in its shadow, 1 in its light, between in a penumbra; an emissive
// mesh's sampled over its surface), as Unity's Shadowmask and Godot's shadowmask hold it. Up
// to four lights share an RGBA atlas, one a channel; lights that light a common texel get
// different channels (greedy, in scene order), so a texel's channel belongs to one light. A light left without a channel (a fifth light
// overlapping four) is counted and reported. Texels no such light reaches hold 1.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bake/chart_texels.h"
#include "bake/lightmap_charts.h"
#include "core/diagnostics.h"
#include "core/parallel.h"
#include "radiosity/solution.h"

namespace radbake {

inline constexpr int kShadowmaskChannels = 4;

// A real-time light of the mask: a punctual light (Light::realtime), or the emissive meshes
// one name gives (Mesh::realtime_light), punctual lights first, each in scene order.
struct ShadowmaskLight {
    std::string name;
    int channel = -1;  // 0-3, -1 when left out of the mask
};

struct Shadowmask {
    std::vector<ShadowmaskLight> lights;        // the real-time lights
    std::vector<std::vector<uint8_t>> images;   // per atlas: RGBA, row 0 at the top, visibility x 255
    std::vector<int> widths, heights;
    size_t lights_without_channel = 0;          // real-time lights left out: overlapping four others
    size_t texels_over_channels = 0;            // texels more than four real-time lights reach
};

// The shadowmask of the scene's real-time lights over the lightmap layout;
// empty (no images) when there are none. `padding` is the layout's: padding texels take their
// nearest covered neighbour's visibility.
Shadowmask bakeShadowmask(const Solution& solution, const LightmapLayout& layout, int padding, ParallelRunner& runner,
                          Diagnostics& diagnostics);

// The same in pieces, for a read-out split by chart: the real-time lights' names and the
// visibility at the texels of the charts `wanted` selects (empty: all), then the mask from
// parts covering every chart (nullopt when they do not, or name other lights). The pieces give
// bakeShadowmask's bytes.
struct ShadowmaskRecords {
    std::vector<std::string> names;  // the real-time lights, in mask order
    ChartRecords records;            // per texel: its reach bits, covered, each light's share
};
ShadowmaskRecords readShadowmaskRecords(const Solution& solution, const LightmapLayout& layout,
                                        std::span<const uint8_t> wanted, ParallelRunner& runner);
std::optional<Shadowmask> assembleShadowmask(const LightmapLayout& layout, int padding,
                                             std::span<const ShadowmaskRecords> parts, const std::string& scene_path,
                                             Diagnostics& diagnostics);

}  // namespace radbake
