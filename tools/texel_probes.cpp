// texel_probes: a probe file at lightmap texels, for the texel accuracy yardstick (issue 27):
// each probe is the world point a bake evaluated for one texel, so a reference
// (tools/reference_mc) at those probes scores the lightmap itself (tools/texel_error.py).
//
//   texel_probes SCENE BAKE_DIR OUT.probes [--count N=400] [--seed S=1] [--threads T=1]
//                [--quality Q=medium] [--texel-density D] [--atlas-size N] [--padding P]
//                [--max-texels N] [--lightmap-scales FILE] [--unit-scale U] [--emission-scale E]
//                [--read-root DIR]...
//
// BAKE_DIR is a `radbake bake SCENE -o BAKE_DIR` folder with lightmaps; the options that shape
// its lightmap layout must be the ones the bake was given (the others do not matter). The
// scene is read and charted as bake() does (back twins, chartBakeLightmaps, packLightmapCharts),
// the atlases named in BAKE_DIR/manifest.json are read, and the layout is checked against
// them: as many atlases of the same sizes, no light outside the charts' padded rectangles, most
// covered texels lit, and the covered and hidden texel counts of its stats.json; else exit 1
// naming what differs.
//
// Of the covered texels that are not hidden inside geometry, N are chosen (deterministic given
// S), the same number from each tenth of them by brightness (max channel), so shadows count as
// much as lit walls. Each line is
//   x y z nx ny nz # atlas A texel I J edge|inside decile D H R G B mesh M NAME
// --same-texels FILE takes the texels (and deciles) a probe file of another bake of the same
// layout lists instead, so that two bakes are scored at the same points by one reference.
// with the texel's sample point (scene file units) and its face's normal, I the atlas column and
// J the row (row 0 at the top), `edge` for a texel the bake evaluates whatever its tolerance
// (chartTexelSites: partly covered or beside a texel that is not fully covered), and H the
// bilinear lookup of the lightmap at the sample point times pi (W/m^2, as probes.csv and
// reference_mc print): what an engine shows there. Exit 2 on a bad command line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "bake/lightmap_adaptive.h"
#include "bake/lightmap_pack.h"
#include "bake/lightmap_seams.h"
#include "cli/option_checks.h"
#include "export/compare_load.h"
#include "export/manifest.h"
#include "radbake.h"
#include "visibility/ray_caster.h"

namespace {

using namespace radbake;
namespace fs = std::filesystem;

constexpr int kDeciles = 10;

struct Args {
    std::string scene, bake_dir, out;
    size_t count = 400;
    uint64_t seed = 1;
    int threads = 1;
    std::string quality = "medium";
    ImportOptions import;
    LightmapSettings lightmaps;
    std::string lightmap_scales;
    std::string same_texels;
};

// One covered, visible texel of the rebuilt layout with the bake's value there.
struct Texel {
    int atlas = 0, x = 0, y = 0;  // atlas column and row
    DVec3 p_world{0.0}, normal{0.0};
    uint32_t mesh = 0;
    bool edge = false;
    DVec3 h{0.0};  // W/m^2
    int decile = 0;
};

// What the atlases hold where the layout says: the check that it is the bake's layout.
struct LayoutCheck {
    size_t covered = 0, hidden = 0, dark_covered = 0, lit_outside = 0;
};

[[noreturn]] void fail(const std::string& why) { throw std::runtime_error(why); }

void addOptions(CLI::App& app, Args& args) {
    app.add_option("scene", args.scene, "Scene file, as baked")->required();
    app.add_option("bake_dir", args.bake_dir, "The bake's output folder (radbake bake -o)")->required();
    app.add_option("out", args.out, "Probe file to write")->required()->check(cli::nonEmptyPath());
    app.add_option("--count", args.count, "Probes to write")->transform(cli::wholeIn(10, 1000000))->capture_default_str();
    app.add_option("--seed", args.seed, "Seed of the choice of texels")->capture_default_str();
    app.add_option("--same-texels", args.same_texels,
                   "Take the texels a probe file of this tool lists (another bake of the same layout)");
    app.add_option("--threads", args.threads, "Threads (0: all cores)")->transform(cli::wholeIn(0, 1024))->capture_default_str();
    app.add_option("--quality", args.quality, "The bake's --quality")
        ->check(CLI::IsMember({"draft", "medium", "high", "reference"}))
        ->capture_default_str();
    cli::addSceneScaleOptions(app, args.import);
    cli::addDaylightOptions(app, args.import.daylight);
    cli::addReadRootOption(app, args.import);
    cli::addLightmapLayoutOptions(app, args.lightmaps, args.lightmap_scales);
}

// The bake's options as its command line set them (the layout's, and the import's).
BakeOptions bakeOptions(const Args& args, Diagnostics& diagnostics) {
    BakeOptions options = BakeOptions::forQuality(qualityNamed(args.quality));
    const double texel_tolerance = options.lightmaps.texel_tolerance;
    options.lightmaps = args.lightmaps;
    options.lightmaps.texel_tolerance = texel_tolerance;
    options.import = args.import;
    if (!args.lightmap_scales.empty()) {
        auto rules = readLightmapScales(args.lightmap_scales, diagnostics);
        if (!rules) fail("cannot read " + args.lightmap_scales);
        options.lightmaps.scales = std::move(*rules);
    }
    return options;
}

LightmapLayout rebuildLayout(const Scene& scene, const BakeOptions& options, Diagnostics& diagnostics) {
    std::optional<LightmapCharts> charts = chartBakeLightmaps(scene, options, diagnostics);
    LightmapLayout layout;
    if (!charts || !packLightmapCharts(std::move(charts->charts), charts->options, layout, diagnostics))
        fail("the scene's lightmaps cannot be charted with these options");
    return layout;
}

// The file bake() writes atlas k to (BakedLightmaps::files), relative to the bake folder.
std::string atlasFile(const Scene& scene, size_t k) {
    return "lightmaps/" + scene.name + "_" + std::to_string(k) + ".exr";
}

// The bake's atlases, in atlas order, by the names bake() gives them, each listed in its manifest.
std::vector<RgbImage> loadAtlases(const fs::path& bake_dir, const Scene& scene, const LightmapLayout& layout) {
    std::string why;
    const std::optional<ManifestContents> manifest = readManifest(bake_dir / kManifestName, why);
    if (!manifest) fail((bake_dir / kManifestName).string() + ": " + why);
    const auto listed = [&](const std::string& file) {
        return std::find(manifest->files.begin(), manifest->files.end(), file) != manifest->files.end();
    };
    std::vector<RgbImage> atlases;
    for (size_t k = 0; k < layout.atlases.size() || listed(atlasFile(scene, k)); ++k) {
        const std::string file = atlasFile(scene, k);
        if (!listed(file)) fail(bake_dir.string() + ": the layout has " + std::to_string(layout.atlases.size()) +
                                " atlases, the bake " + std::to_string(k) + " (no " + file + ")");
        if (k >= layout.atlases.size()) fail(bake_dir.string() + ": the bake has more atlases than the layout's " +
                                             std::to_string(layout.atlases.size()) + " (" + file + ")");
        atlases.push_back(loadExrFile(bake_dir / file));
        const LightmapAtlas& want = layout.atlases[k];
        if (atlases.back().width != want.width || atlases.back().height != want.height)
            fail(file + " is " + std::to_string(atlases.back().width) + " x " + std::to_string(atlases.back().height) +
                 ", the layout's atlas " + std::to_string(want.width) + " x " + std::to_string(want.height));
    }
    return atlases;
}

DVec3 atlasValue(const RgbImage& image, int x, int y) {
    const float* t = &image.rgb[3 * (static_cast<size_t>(y) * image.width + x)];
    return DVec3(t[0], t[1], t[2]);
}

double brightness(const DVec3& h) { return std::max({h.x, h.y, h.z}); }

// Texels holding light outside every chart's padded rectangle: none when the layout is the bake's.
size_t litOutsideCharts(const LightmapLayout& layout, const std::vector<RgbImage>& atlases, int padding) {
    std::vector<std::vector<uint8_t>> inside(atlases.size());
    for (size_t k = 0; k < atlases.size(); ++k) inside[k].assign(atlases[k].rgb.size() / 3, 0);
    for (const LightmapChart& chart : layout.charts) {
        if (chart.atlas < 0) continue;
        const RgbImage& image = atlases[chart.atlas];
        for (int y = std::max(chart.y - padding, 0); y < std::min(chart.y + chart.height + padding, image.height); ++y)
            for (int x = std::max(chart.x - padding, 0); x < std::min(chart.x + chart.width + padding, image.width); ++x)
                inside[chart.atlas][static_cast<size_t>(y) * image.width + x] = 1;
    }
    size_t lit = 0;
    for (size_t k = 0; k < atlases.size(); ++k)
        for (size_t t = 0; t < inside[k].size(); ++t)
            lit += !inside[k][t] && brightness(atlasValue(atlases[k], static_cast<int>(t % atlases[k].width),
                                                          static_cast<int>(t / atlases[k].width))) != 0.0;
    return lit;
}

// Every covered texel of every placed chart that is not hidden, with the bake's value there.
std::vector<Texel> coveredTexels(const LightmapLayout& layout, const std::vector<RgbImage>& atlases,
                                 ParallelRunner& runner, const HiddenTest& hidden, LayoutCheck& check) {
    std::vector<Texel> texels;
    // The atlases as the bake's lookups read them (bilinearLookup).
    std::vector<LightmapImage> images(atlases.size());
    for (size_t k = 0; k < atlases.size(); ++k)
        images[k] = LightmapImage{.width = atlases[k].width, .height = atlases[k].height, .rgb = atlases[k].rgb, .state = {}};
    for (const LightmapChart& chart : layout.charts) {
        if (chart.atlas < 0) continue;
        const std::vector<TexelSite> sites = chartTexelSites(chart, runner, hidden);
        for (size_t t = 0; t < sites.size(); ++t) {
            const TexelSite& site = sites[t];
            check.hidden += site.hidden;
            if (site.cover == TexelCover::Empty) continue;
            const ChartFace& face = chart.faces[site.face];
            Texel texel{.atlas = chart.atlas,
                        .x = chart.x + static_cast<int>(t % chart.width),
                        .y = chart.y + static_cast<int>(t / chart.width),
                        .p_world = face.worldPoint(site.p_plane),
                        .normal = face.normal_world,
                        .mesh = chart.mesh,
                        .edge = site.edge};
            // What an engine shows at the sample point: the bilinear lookup there, the texel's own
            // value only where the point is its centre.
            texel.h = kPi * bilinearLookup(images[chart.atlas], chart.atlasTexel(site.p_plane));
            check.dark_covered += !(brightness(texel.h) > 0.0);
            texels.push_back(texel);
        }
    }
    check.covered = texels.size();
    return texels;
}

// The whole number after `"key":` in the bake's stats.json, or -1 when it has none (a bake
// without lightmaps, an older stats.json).
long long statsCount(const fs::path& bake_dir, const std::string& key) {
    std::ifstream file(bake_dir / "stats.json");
    const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const size_t at = text.find("\"" + key + "\":");
    return at == std::string::npos ? -1 : std::atoll(text.c_str() + at + key.size() + 3);
}

void checkCount(const std::string& bake_dir, const std::string& key, size_t rebuilt) {
    const long long baked = statsCount(bake_dir, key);
    if (baked >= 0 && static_cast<size_t>(baked) != rebuilt)
        fail(bake_dir + "/stats.json: " + key + " " + std::to_string(baked) + ", the rebuilt layout's " +
             std::to_string(rebuilt) + ": not this layout's bake (other options?)");
}

// A layout that is not the bake's puts light outside its charts, leaves its charts dark or
// counts other texels.
void checkLayout(const LayoutCheck& check, const std::string& bake_dir) {
    checkCount(bake_dir, "covered_texels", check.covered);
    checkCount(bake_dir, "hidden_texels", check.hidden);
    if (check.lit_outside > 0)
        fail(bake_dir + ": " + std::to_string(check.lit_outside) +
             " texels hold light outside the rebuilt layout's charts: not this layout's bake (other options?)");
    if (check.covered == 0 || 2 * check.dark_covered > check.covered)
        fail(bake_dir + ": " + std::to_string(check.dark_covered) + " of the layout's " +
             std::to_string(check.covered) + " covered texels are black: not this layout's bake (other options?)");
}

// `count` texels, an equal share (the first count % 10 deciles one more) drawn without
// replacement from each tenth of them by brightness; ordered by decile, atlas, row, column.
std::vector<Texel> chooseStratified(const std::vector<Texel>& texels, size_t count, uint64_t seed) {
    if (count > texels.size())
        fail("asked for " + std::to_string(count) + " probes, the bake has " + std::to_string(texels.size()) +
             " covered texels");
    std::vector<size_t> order(texels.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return brightness(texels[a].h) < brightness(texels[b].h); });
    std::mt19937_64 random(seed);  // its output is fixed by the standard; std's distributions are not
    std::vector<Texel> chosen;
    const size_t n = texels.size();
    for (int d = 0; d < kDeciles; ++d) {
        const size_t begin = n * d / kDeciles, end = n * (d + 1) / kDeciles;
        const size_t quota = std::min(end - begin, count / kDeciles + (static_cast<size_t>(d) < count % kDeciles));
        for (size_t k = begin; k < begin + quota; ++k) {
            std::swap(order[k], order[k + random() % (end - k)]);
            chosen.push_back(texels[order[k]]);
            chosen.back().decile = d;
        }
    }
    std::sort(chosen.begin(), chosen.end(), [](const Texel& a, const Texel& b) {
        return std::tie(a.decile, a.atlas, a.y, a.x) < std::tie(b.decile, b.atlas, b.y, b.x);
    });
    return chosen;
}

std::string probeLine(const Texel& t, const Scene& scene, double file_per_metre) {
    const DVec3 p = t.p_world * file_per_metre;
    const std::string& name = scene.meshes[t.mesh].name;
    char line[512];
    std::snprintf(line, sizeof line,
                  "%.9g %.9g %.9g %.9g %.9g %.9g # atlas %d texel %d %d %s decile %d H %.6g %.6g %.6g mesh %u %s\n",
                  p.x, p.y, p.z, t.normal.x, t.normal.y, t.normal.z, t.atlas, t.x, t.y, t.edge ? "edge" : "inside",
                  t.decile, t.h.x, t.h.y, t.h.z, t.mesh, name.empty() ? "-" : name.c_str());
    return line;
}

// The texels `path` (a probe file this tool wrote) lists, in its order and with its deciles.
std::vector<Texel> chooseListed(const std::vector<Texel>& texels, const std::string& path) {
    std::map<std::tuple<int, int, int>, const Texel*> by_position;
    for (const Texel& t : texels) by_position[{t.atlas, t.x, t.y}] = &t;
    std::ifstream in(path);
    if (!in) fail("cannot read " + path);
    std::vector<Texel> chosen;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const size_t at = line.find("# atlas ");
        if (line.empty() || line[0] == '#' || at == std::string::npos) continue;
        int atlas = 0, x = 0, y = 0, decile = 0;
        char edge[16] = {};
        if (std::sscanf(line.c_str() + at, "# atlas %d texel %d %d %15s decile %d", &atlas, &x, &y, edge, &decile) != 5)
            fail(path + ":" + std::to_string(number) + ": no texel in its comment");
        const auto found = by_position.find({atlas, x, y});
        if (found == by_position.end())
            fail(path + ":" + std::to_string(number) + ": atlas " + std::to_string(atlas) + " texel " +
                 std::to_string(x) + " " + std::to_string(y) + " is not a covered, visible texel of this bake");
        chosen.push_back(*found->second);
        chosen.back().decile = decile;
    }
    return chosen;
}

void writeProbes(const Args& args, const std::vector<Texel>& chosen, const Scene& scene) {
    std::ostringstream out;
    out << "# texel probes of " << args.scene << " for the bake in " << args.bake_dir << " (tools/texel_probes, seed "
        << args.seed << "): the sample points of " << chosen.size()
        << " covered texels, an equal share of each brightness decile\n";
    for (const Texel& t : chosen) out << probeLine(t, scene, 1.0 / static_cast<double>(args.import.unit_scale));
    const std::string temporary = args.out + ".tmp";
    std::ofstream file(temporary, std::ios::binary);
    file << out.str();
    file.close();
    if (!file || std::rename(temporary.c_str(), args.out.c_str()) != 0) fail("cannot write " + args.out);
}

int run(const Args& args) {
    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) {
        if (d.severity != Severity::Note) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
    };
    const BakeOptions options = bakeOptions(args, diagnostics);
    std::optional<Scene> scene = importScene(args.scene, options.import, diagnostics);
    if (!scene) return 1;
    addBackTwins(*scene);  // as bake() does before every stage
    const LightmapLayout layout = rebuildLayout(*scene, options, diagnostics);
    const std::vector<RgbImage> atlases = loadAtlases(args.bake_dir, *scene, layout);
    ParallelRunner runner(Threading{.threads = args.threads});
    // The bake's hidden texels (left to dilation), found as bakeLightmaps finds them.
    const std::unique_ptr<RayCaster> rays = RayCaster::build(*scene, diagnostics, runner.threads());
    if (!rays) return 1;
    const HiddenTest hidden = [&](const SurfacePoint& at) {
        return insideGeometry(*scene, *rays, at.p_world, at.normal_world);
    };
    LayoutCheck check;
    check.lit_outside = litOutsideCharts(layout, atlases, options.lightmaps.padding);
    const std::vector<Texel> texels = coveredTexels(layout, atlases, runner, hidden, check);
    checkLayout(check, args.bake_dir);
    const std::vector<Texel> chosen =
        args.same_texels.empty() ? chooseStratified(texels, args.count, args.seed) : chooseListed(texels, args.same_texels);
    writeProbes(args, chosen, *scene);
    const size_t edges = std::count_if(texels.begin(), texels.end(), [](const Texel& t) { return t.edge; });
    std::fprintf(stderr,
                 "texel_probes: %zu probes from %zu covered texels (%zu edge, %zu black; %zu hidden left out) in %zu "
                 "atlas(es), %zu charts\n",
                 chosen.size(), texels.size(), edges, check.dark_covered, check.hidden, atlases.size(),
                 layout.charts.size());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Probes at the sample points of a bake's lightmap texels (issue 27's texel yardstick)"};
    Args args;
    addOptions(app, args);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        return run(args);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "texel_probes: error: %s\n", e.what());
        return 1;
    }
}
