// The library's whole bake (src/radbake.h): the same answers as the stages called one by
// one, fit to run inside another program (side by side, cancelled, no process-wide limits),
// and all-or-nothing writing.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "radbake.h"
#include "../export/temp_files.h"
#include "../radiosity/test_scenes.h"

using namespace radbake;
using namespace radbake::test;
using testfs::TempDir;

namespace {

// A closed grey room lit by a ceiling lamp, with a block on the floor: occlusion, bounces,
// several charts. In metres.
Scene litRoom() {
    Scene scene;
    scene.name = "lit_room";
    const uint32_t grey = addMaterial(scene, Vec3(0.6f), Vec3(0.0f));
    const uint32_t lamp = addMaterial(scene, Vec3(0.0f), Vec3(5.0f));
    addInwardBox(scene, grey, Vec3(0.0f), Vec3(2.0f));
    addOutwardBox(scene, grey, Vec3(0.7f, 0.7f, 0.0f), Vec3(1.2f, 1.2f, 0.6f));
    // The lamp, just under the ceiling (z = 2), facing down.
    addQuad(scene, lamp, {0.8f, 0.8f, 1.99f}, {0.8f, 1.2f, 1.99f}, {1.2f, 1.2f, 1.99f}, {1.2f, 0.8f, 1.99f});
    return scene;
}

BakeOptions draftOptions(int threads) {
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.threading.threads = threads;
    Probe on_floor, on_wall;
    on_floor.position = {0.3, 0.3, 0.01};
    on_floor.normal = {0.0, 0.0, 1.0};
    on_wall.position = {0.01, 1.0, 1.0};
    on_wall.normal = {1.0, 0.0, 0.0};
    options.probes = std::vector<Probe>{on_floor, on_wall};
    return options;
}

Bake bakeQuietly(const Scene& scene, const BakeOptions& options) {
    Progress progress(false);
    Diagnostics diagnostics;
    Bake result = bake(scene, options, progress, diagnostics);
    for (const Diagnostic& d : diagnostics.all()) MESSAGE(formatDiagnostic(d));
    return result;
}

// Bit-for-bit equality of everything a bake computes.
void checkSameBake(const Bake& a, const Bake& b) {
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(a.vertices.values == b.vertices.values);
    CHECK(a.probe_irradiance == b.probe_irradiance);
    REQUIRE(a.lightmaps.has_value() == b.lightmaps.has_value());
    if (!a.lightmaps) return;
    REQUIRE(a.lightmaps->lightmaps.images.size() == b.lightmaps->lightmaps.images.size());
    for (size_t k = 0; k < a.lightmaps->lightmaps.images.size(); ++k)
        CHECK(a.lightmaps->lightmaps.images[k].rgb == b.lightmaps->lightmaps.images[k].rgb);
    CHECK(a.report.solve.links == b.report.solve.links);
}

}  // namespace

TEST_CASE("BakeOptions: the default is medium, and forQuality sets every preset, the texel tolerance included") {
    const BakeOptions defaults;
    const BakeOptions medium = BakeOptions::forQuality(Quality::Medium);
    CHECK(std::string(toString(defaults.solver.quality)) == "medium");
    CHECK(defaults.solver.error_threshold == medium.solver.error_threshold);
    CHECK(defaults.solver.min_element_area == medium.solver.min_element_area);
    CHECK(defaults.lightmaps.texel_tolerance == medium.lightmaps.texel_tolerance);
    CHECK(BakeOptions::forQuality(Quality::Draft).lightmaps.texel_tolerance == 0.05);
    CHECK(BakeOptions::forQuality(Quality::Reference).lightmaps.texel_tolerance == 0.0);
    CHECK(BakeOptions::forQuality(Quality::High).solver.error_threshold ==
          SolverOptions::forQuality(Quality::High).error_threshold);
    CHECK_FALSE(defaults.threading.pin);  // a library pins only when asked
}

TEST_CASE("bake() gives what the stages give when called one by one") {
    const Scene scene = litRoom();
    const BakeOptions options = draftOptions(2);
    const Bake whole = bakeQuietly(scene, options);
    REQUIRE(whole.ok());

    Diagnostics diagnostics;
    Progress progress(false);
    ParallelRunner runner(options.threading);
    const PartSet parts = buildParts(scene, PartOptions{}, diagnostics);
    const std::optional<Solution> solution =
        solveRadiosity(scene, parts, options.solver, runner, progress, diagnostics);
    REQUIRE(solution);
    CHECK(bakeVertices(scene, *solution, ReadoutOptions::forQuality(solution->options.quality), runner).values ==
          whole.vertices.values);
    LightmapOptions lightmap_options;
    lightmap_options.texel_tolerance = options.lightmaps.texel_tolerance;
    const std::optional<LightmapCharts> charts =
        chartLightmapsWithinBudget(scene, lightmap_options, LightmapBudget{}, diagnostics);
    REQUIRE(charts);
    Lightmaps lightmaps;
    REQUIRE(bakeLightmaps(scene, *solution, ReadoutOptions::forQuality(solution->options.quality), *charts, runner,
                          lightmaps, diagnostics));
    REQUIRE(whole.lightmaps);
    REQUIRE(lightmaps.images.size() == whole.lightmaps->lightmaps.images.size());
    for (size_t k = 0; k < lightmaps.images.size(); ++k)
        CHECK(lightmaps.images[k].rgb == whole.lightmaps->lightmaps.images[k].rgb);
    REQUIRE(whole.probe_irradiance.size() == 2);
    CHECK(whole.probe_irradiance[0] == probeIrradiance(*solution, ReadoutOptions::forQuality(solution->options.quality),
                                                       DVec3(0.3, 0.3, 0.01), DVec3(0.0, 0.0, 1.0)));
    CHECK(whole.probe_irradiance[0].x > 0.0);
    CHECK(whole.report.solve.links == solution->stats.links);
    CHECK(whole.report.lightmaps.covered_texels == lightmaps.covered_texels);
    CHECK_FALSE(diagnostics.hasErrors());
}

TEST_CASE("two bakes side by side in one process give the bytes of one bake alone, on any thread count") {
    const Scene scene = litRoom();
    const Bake alone = bakeQuietly(scene, draftOptions(1));
    Bake first, second;
    std::thread a([&] { first = bakeQuietly(scene, draftOptions(2)); });
    std::thread b([&] { second = bakeQuietly(scene, draftOptions(1)); });
    a.join();
    b.join();
    checkSameBake(alone, first);
    checkSameBake(alone, second);
}

TEST_CASE("a bake sets no process-wide TBB limit, whatever its thread count") {
    const auto limit = [] { return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism); };
    const size_t before = limit();
    // Seen from inside the bake (every phase after the ray caster is built) and after it.
    Progress progress(false);
    std::atomic<bool> limited{false};
    progress.setSink([&](const ProgressEvent&) {
        if (limit() != before) limited = true;
    });
    Diagnostics diagnostics;
    REQUIRE(bake(litRoom(), draftOptions(1), progress, diagnostics).ok());
    CHECK_FALSE(limited.load());
    CHECK(limit() == before);
}

TEST_CASE("cancelled from the progress sink: the bake stops in that phase and nothing is written") {
    for (const std::string phase : {"links", "vertices", "lightmaps"}) {
        CAPTURE(phase);
        Progress progress(false);
        std::vector<std::string> seen;
        progress.setSink([&](const ProgressEvent& event) {
            if (event.phase_done) return;
            if (seen.empty() || seen.back() != event.phase) seen.emplace_back(event.phase);
            if (event.phase == phase) progress.cancel();
        });
        Diagnostics diagnostics;
        const Bake cancelled = bake(litRoom(), draftOptions(2), progress, diagnostics);
        CHECK(std::string(toString(cancelled.status)) == "cancelled");
        CHECK_FALSE(diagnostics.hasErrors());
        REQUIRE_FALSE(seen.empty());
        CHECK(seen.back() == phase);  // no phase began after the one that cancelled

        const TempDir dir;
        const std::filesystem::path out = dir.path / "out";
        Diagnostics write_diagnostics;
        CHECK_FALSE(writeBake(cancelled, out, write_diagnostics));
        CHECK(write_diagnostics.hasErrors());
        CHECK_FALSE(std::filesystem::exists(out));
    }
}

TEST_CASE("the progress sink sees every phase begin and end, fractions within [0, 1]") {
    Progress progress(false);
    std::vector<std::string> begun, ended;
    bool fractions_ok = true;
    progress.setSink([&](const ProgressEvent& event) {
        fractions_ok = fractions_ok && event.fraction >= 0.0 && event.fraction <= 1.0 && event.total_seconds >= 0.0;
        if (event.phase_done) ended.emplace_back(event.phase);
        else if (begun.empty() || begun.back() != event.phase) begun.emplace_back(event.phase);
    });
    Diagnostics diagnostics;
    REQUIRE(bake(litRoom(), draftOptions(2), progress, diagnostics).ok());
    CHECK(fractions_ok);
    CHECK(begun == ended);
    // The room's cluster links from unlit surfaces wait for the first solve (solver.cpp); the
    // last round's deferred passes repeat while they light new sources (the third finds none).
    const std::vector<std::string> expected = {
        "parts",          "elements",           "direct light",         "links",
        "solve",          "links (deferred)",   "solve (deferred)",     "links (deferred 2)",
        "solve (deferred 2)", "links (deferred 3)", "vertices",         "lightmaps",
        "probes"};
    CHECK(begun == expected);
}

TEST_CASE("the solve's phases report its fraction and time left: in [0, 1], never falling back, only there") {
    Progress progress(false);
    bool ok = true, known = false;
    double last = 0.0;
    std::vector<std::string> outside;  // phases that reported a stage without being the solve's
    progress.setSink([&](const ProgressEvent& event) {
        const bool readout = event.phase == "vertices" || event.phase == "lightmaps" || event.phase == "probes";
        if (readout != event.stage.empty()) outside.emplace_back(event.phase);
        if (event.stage.empty()) return;
        if (!(event.stage_fraction >= last && event.stage_fraction <= 1.0 && event.stage_seconds_left >= 0.0))
            MESSAGE(std::string(event.phase), " ", event.stage_fraction, " after ", last, " left ", event.stage_seconds_left);
        ok = ok && event.stage_fraction >= last && event.stage_fraction <= 1.0 && event.stage_seconds_left >= 0.0;
        last = event.stage_fraction;
        known = known || event.stage_fraction > 0.0;
    });
    Diagnostics diagnostics;
    REQUIRE(bake(litRoom(), draftOptions(2), progress, diagnostics).ok());
    CHECK(ok);
    CHECK(known);  // from the first links phase on (the solver said what follows)
    CHECK(outside.empty());
}

TEST_CASE("writeBake writes every output of an Ok bake, and nothing for a failed one") {
    const Bake good = bakeQuietly(litRoom(), draftOptions(2));
    REQUIRE(good.ok());
    const TempDir dir;
    Diagnostics diagnostics;
    REQUIRE(writeBake(good, dir.path / "good", diagnostics));
    for (const char* file : {"lit_room.glb", "lit_room.ply", "lightmaps/lit_room_0.exr", "probes.csv", "stats.json",
                             "manifest.json"})
        CHECK_MESSAGE(std::filesystem::is_regular_file(dir.path / "good" / file), file);

    Scene empty;
    empty.name = "empty";
    Diagnostics bad_diagnostics;
    Progress progress(false);
    const Bake bad = bake(empty, BakeOptions{}, progress, bad_diagnostics);
    CHECK(std::string(toString(bad.status)) == "input error");
    CHECK(bad_diagnostics.hasErrors());
    CHECK_FALSE(writeBake(bad, dir.path / "bad", bad_diagnostics));
    CHECK_FALSE(std::filesystem::exists(dir.path / "bad"));
}

namespace {

Scene scaled(Scene scene, float s) {
    for (Mesh& mesh : scene.meshes)
        for (Vec3& p : mesh.positions) p *= s;
    return scene;
}

}  // namespace

TEST_CASE("lightmaps are scale invariant: the same texels per object at 1e-4, 1 and 1e6 give the same atlases") {
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.threading.threads = 2;
    options.lightmaps.texels_per_unit = 8.0;
    const Bake unit = bakeQuietly(litRoom(), options);
    REQUIRE(unit.ok());
    const Lightmaps& reference = unit.lightmaps->lightmaps;
    for (const float s : {1e-4f, 1e6f}) {
        CAPTURE(s);
        BakeOptions at_scale = options;
        at_scale.lightmaps.texels_per_unit = 8.0 / s;
        const Bake other = bakeQuietly(scaled(litRoom(), s), at_scale);
        REQUIRE(other.ok());
        const Lightmaps& maps = other.lightmaps->lightmaps;
        CHECK(maps.layout.charts.size() == reference.layout.charts.size());
        CHECK(maps.covered_texels == reference.covered_texels);
        REQUIRE(maps.images.size() == reference.images.size());
        // Float rounding of the scaled positions (1e-7 relative) can flip a grazing shadow ray
        // where the block stands on the floor (as in the solver's own invariance test), and
        // with it a decision that follows (a block interpolated or evaluated, an edge sample
        // taking its neighbours' mean): the sum of the light within 2e-3, the worst texel
        // within 6 % of the brightest (3.2 % at 1e6 since the link reconstruction, in a
        // padding texel of the seam fit; 4.9 % since the floor is cut along the block,
        // contact_cuts.h, where two neighbouring texels at the block's foot trade light, with
        // the same roots and links at both scales). Since the ceiling is cut along the lamp's
        // outline (contact_cuts.h), a split of a whole block face (y = 0.7) flips too: made at
        // scale 1, not at 1e-4 or 1e6 (493 against 489 elements), and the sum moves by 1.4e-3.
        // The last round's repeated deferred passes follow such flips one bounce further: the
        // worst texel within 7 %.
        double worst = 0.0, brightest = 0.0, sum = 0.0, sum_reference = 0.0;
        for (size_t k = 0; k < maps.images.size(); ++k) {
            REQUIRE(maps.images[k].rgb.size() == reference.images[k].rgb.size());
            for (size_t t = 0; t < maps.images[k].rgb.size(); ++t) {
                const double a = maps.images[k].rgb[t], b = reference.images[k].rgb[t];
                worst = std::max(worst, std::fabs(a - b));
                brightest = std::max(brightest, b);
                sum += a;
                sum_reference += b;
            }
        }
        MESSAGE("scale " << s << ": worst texel " << worst / brightest << " of the brightest, sum "
                         << sum / sum_reference - 1.0);
        CHECK(brightest > 0.0);
        CHECK(worst <= 0.07 * brightest);
        CHECK(sum == doctest::Approx(sum_reference).epsilon(2e-3).scale(0.0));
    }
}

TEST_CASE("at a default density a million times too fine, the budget applies before any chart is built") {
    // 2e6 m walls at 16 texels/m would be 1e15 texels: the charts alone would exhaust memory.
    BakeOptions options = BakeOptions::forQuality(Quality::Draft);
    options.lightmaps.max_texels = 20000;
    Progress progress(false);
    Diagnostics diagnostics;
    const Bake huge = bake(scaled(litRoom(), 1e6f), options, progress, diagnostics);
    REQUIRE(huge.ok());
    CHECK(huge.report.lightmaps.covered_texels <= 20000);
    CHECK(huge.report.lightmaps.covered_texels > 20000 / 8);  // lowered to fit, not to nothing
    CHECK(huge.options.lightmaps.texels_per_unit < 16.0 * 1e-4);
    CHECK(diagnostics.warningCount() == 1);
    // A density the user gave is an error naming one that fits, also before building charts.
    options.lightmaps.texels_per_unit = 16.0;
    Diagnostics given_diagnostics;
    Progress given_progress(false);
    const Bake refused = bake(scaled(litRoom(), 1e6f), options, given_progress, given_diagnostics);
    CHECK_FALSE(refused.ok());
    REQUIRE(given_diagnostics.hasErrors());
    CHECK(given_diagnostics.all().back().message.find("give a density of about") != std::string::npos);
}

// radbake.h redeclares every stage; a redeclaration that drifted from its stage header would
// be a second overload, which decltype of the name (and every call) rejects.
static_assert(std::is_same_v<decltype(&importScene),
                             std::optional<Scene> (*)(const std::string&, const ImportOptions&, Diagnostics&)>);
static_assert(std::is_same_v<decltype(&buildParts), PartSet (*)(const Scene&, const PartOptions&, Diagnostics&)>);
static_assert(std::is_same_v<decltype(&solveRadiosity),
                             std::optional<Solution> (*)(const Scene&, const PartSet&, const SolverOptions&,
                                                         ParallelRunner&, Progress&, Diagnostics&)>);
static_assert(std::is_same_v<decltype(&bakeVertices),
                             VertexBake (*)(const Scene&, const Solution&, const ReadoutOptions&, ParallelRunner&,
                                            Progress*)>);
static_assert(std::is_same_v<decltype(&chartLightmapsWithinBudget),
                             std::optional<LightmapCharts> (*)(const Scene&, LightmapOptions, const LightmapBudget&,
                                                               Diagnostics&)>);
static_assert(std::is_same_v<decltype(&bakeLightmaps),
                             bool (*)(const Scene&, const Solution&, const ReadoutOptions&, LightmapCharts,
                                      ParallelRunner&, Lightmaps&, Diagnostics&, Progress*)>);
static_assert(std::is_same_v<decltype(&writeBake),
                             bool (*)(const Bake&, const std::filesystem::path&, Diagnostics&, WrittenBake*)>);
static_assert(std::is_same_v<decltype(&commitBake),
                             bool (*)(const Bake&, OutputTransaction&, Diagnostics&, WrittenBake*)>);
static_assert(std::is_same_v<decltype(&bakeInto),
                             bool (*)(const std::string&, const std::filesystem::path&, const BakeOptions&, Progress&,
                                      Diagnostics&, Bake*, WrittenBake*)>);

TEST_CASE("a bake over its memory budget stops with an error naming the budget, and writes nothing") {
    BakeOptions options = draftOptions(2);
    options.solver.max_memory_mb = 1.0;  // below any process's resident memory
    Progress progress(false);
    Diagnostics diagnostics;
    const Bake over = bake(litRoom(), options, progress, diagnostics);
    CHECK_FALSE(over.ok());
    REQUIRE(diagnostics.hasErrors());
    const std::string message = diagnostics.all().back().message;
    CHECK(message.find("memory budget of 1 MiB") != std::string::npos);
    CHECK(message.find("--max-memory") != std::string::npos);
    // The default budget is the machine's: a bake well within it runs.
    options.solver.max_memory_mb = 0.0;
    CHECK(bakeQuietly(litRoom(), options).ok());
}

// Every output of a bake written into `dir` but timings.json (what the run cost), by name.
std::map<std::string, std::string> writtenBytes(const Bake& baked, const std::filesystem::path& dir) {
    Diagnostics diagnostics;
    REQUIRE(writeBake(baked, dir, diagnostics));
    std::map<std::string, std::string> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir))
        if (entry.is_regular_file() && entry.path().filename() != "timings.json")
            files[std::filesystem::relative(entry.path(), dir).string()] = testfs::readBytes(entry.path());
    return files;
}

TEST_CASE("a read-out-only change reuses the saved solution and writes a fresh bake's bytes") {
    const Scene scene = litRoom();
    TempDir dir;
    BakeOptions options = BakeOptions::forQuality(Quality::Medium);
    options.threading.threads = 2;
    options.probes = std::vector<Probe>{{DVec3(0.3, 0.3, 0.01), DVec3(0.0, 0.0, 1.0), {}}};
    options.solution_file = (dir.path / "lit_room.solution").string();
    const Bake first = bakeQuietly(scene, options);
    REQUIRE(first.ok());
    const auto solved = [](const Bake& b) {
        return std::any_of(b.report.phases.begin(), b.report.phases.end(),
                           [](const auto& phase) { return phase.first.rfind("links", 0) == 0; });
    };
    REQUIRE(solved(first));
    // Every read-out knob changed at once, and the texel tolerance: none changes the solution.
    options.readout = ReadoutOptions::forQuality(Quality::High);
    options.readout.edge_correction = EdgeCorrection::Shared;
    options.lightmaps.texel_tolerance = 0.005;
    const Bake reused = bakeQuietly(scene, options);
    CHECK_FALSE(solved(reused));
    BakeOptions fresh_options = options;
    fresh_options.solution_file.clear();
    const Bake fresh = bakeQuietly(scene, fresh_options);
    REQUIRE(solved(fresh));
    const auto reused_files = writtenBytes(reused, dir.path / "reused");
    const auto fresh_files = writtenBytes(fresh, dir.path / "fresh");
    CHECK(reused_files.size() >= 5);  // glb, PLY, EXR and PNG atlases, probes, stats, manifest
    CHECK(reused_files == fresh_files);
    // The read-out did change what was read: the first bake's vertices differ.
    CHECK(first.vertices.values != reused.vertices.values);
}

TEST_CASE("a saved solution is reused by a bake with other lightmap settings, and gives a fresh bake's outputs") {
    const Scene scene = litRoom();
    TempDir dir;
    BakeOptions options = draftOptions(2);
    options.solution_file = (dir.path / "lit_room.solution").string();
    const Bake first = bakeQuietly(scene, options);
    REQUIRE(first.ok());
    REQUIRE(std::filesystem::exists(options.solution_file));
    const auto solved = [](const Bake& b) {
        return std::any_of(b.report.phases.begin(), b.report.phases.end(),
                           [](const auto& phase) { return phase.first.rfind("links", 0) == 0; });
    };
    CHECK(solved(first));

    // Another density and padding: the solution is read back, not solved again, and every
    // output is what a bake without the file gives.
    options.lightmaps.texels_per_unit = 24.0;
    options.lightmaps.padding = 3;
    const Bake reused = bakeQuietly(scene, options);
    CHECK_FALSE(solved(reused));
    BakeOptions fresh_options = options;
    fresh_options.solution_file.clear();
    const Bake fresh = bakeQuietly(scene, fresh_options);
    checkSameBake(fresh, reused);
    CHECK(reused.report.solve.elements == fresh.report.solve.elements);
    CHECK(reused.report.solve.rays == fresh.report.solve.rays);

    // Other solver settings: solved again (and saved for them).
    options.solver.error_threshold *= 0.5;
    const Bake resolved = bakeQuietly(scene, options);
    REQUIRE(resolved.ok());
    CHECK(solved(resolved));
    // Another scene: solved again.
    Scene moved = scene;
    moved.meshes.back().positions[0].x += 0.01f;
    CHECK(solved(bakeQuietly(moved, options)));
}
