#include "pipeline/shards.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include "core/binary_records.h"
#include "core/regular_file.h"
#include "pipeline/bake_stages.h"
#include "pipeline/solution_cache.h"
#include "readout/realtime_emission.h"

namespace radbake {
namespace {

constexpr char kPartMagic[] = "radbake read-out part 3\n";

// Read-out shards per rank of a bake on ranks (readOutAcrossRanks).
constexpr uint32_t kShardsPerRank = 8;

std::string partName(const ReadoutPart& part) {
    return "shard " + std::to_string(part.shard) + " of " + std::to_string(part.shards);
}

void writeString(Writer& w, const std::string& s) { w.array(std::vector<char>(s.begin(), s.end())); }
void readString(Reader& r, std::string& s) {
    std::vector<char> chars;
    r.array(chars);
    s.assign(chars.begin(), chars.end());
}

// The parts in shard order, checked to be shards 1..N of one read-out of this scene and
// solution; false after reporting, naming the part at fault.
bool checkParts(const std::vector<ReadoutPart>& parts, const std::string& inputs_sha256, const std::string& key,
                const SourceLocation& scene, Diagnostics& diagnostics) {
    if (parts.empty()) {
        diagnostics.error(scene, "no read-out part to merge");
        return false;
    }
    const uint32_t shards = parts.front().shards;
    bool ok = true;
    for (const ReadoutPart& part : parts) {
        const SourceLocation where{part.folder, 0, 0};
        if (part.shards != shards) {
            diagnostics.error(where, "is " + partName(part) + ", but " + parts.front().folder + " is of " +
                                         std::to_string(shards) + ": parts of one read-out only");
            ok = false;
        } else if (part.inputs_sha256 != inputs_sha256) {
            diagnostics.error(where, "was read from other scene files than " + scene.file + " holds now");
            ok = false;
        } else if (part.solution_key != key) {
            diagnostics.error(where, "was read from another solution (other solver settings or another scene)");
            ok = false;
        }
    }
    if (!ok) return false;
    for (uint32_t k = 1; k <= shards; ++k) {
        const auto count = std::count_if(parts.begin(), parts.end(), [&](const ReadoutPart& p) { return p.shard == k; });
        if (count == 1) continue;
        diagnostics.error(scene, (count == 0 ? "shard " : "more than one part of shard ") + std::to_string(k) + " of " +
                                     std::to_string(shards) + (count == 0 ? " is missing" : ""));
        ok = false;
    }
    return ok;
}

// prepareStages for a gather or a merge, the lightmap charts placed; false when stopped.
bool prepareShardStep(StageRun& run, std::optional<LightmapLayout>& layout,
                      std::optional<LightmapOptions>& used) {
    std::optional<LightmapCharts> charts;
    if (!prepareStages(run, charts)) return false;
    if (!charts) return true;
    used = charts->options;
    layout.emplace();
    if (!packLightmapCharts(std::move(charts->charts), *used, *layout, run.diagnostics)) return !run.stopped();
    return !run.stopped();
}

// Shard part.shard of part.shards of the read-out, from out.solution, into `part`; false when stopped.
bool readShard(StageRun& run, const LightmapLayout* lightmap_layout, const LightmapOptions* lightmap_options,
               ReadoutPart& part) {
    Bake& out = run.out;
    const Scene& scene = *out.scene;
    const uint32_t shard = part.shard, shards = part.shards;
    const RealtimeEmissionLeftOut realtime_emission(*out.solution);
    const ReadoutOptions readout = readoutOptionsOf(out.options);
    run.beginPhase("vertices");
    const auto [begin, end] = shardRange(vertexPointCosts(scene), shard, shards);
    part.vertices = readVertexPoints(scene, *out.solution, readout, run.runner, begin, end, &run.progress);
    if (run.stopped()) return false;
    if (lightmap_layout) {
        const LightmapLayout& layout = *lightmap_layout;
        const LightmapOptions& used = *lightmap_options;
        run.beginPhase("lightmaps");
        std::vector<double> texels;
        for (const LightmapChart& chart : layout.charts)
            texels.push_back(chart.atlas < 0 ? 0.0 : static_cast<double>(chart.width) * chart.height);
        const auto [first, last] = shardRange(texels, shard, shards);
        std::vector<uint8_t> wanted(layout.charts.size(), 0);
        std::fill(wanted.begin() + static_cast<std::ptrdiff_t>(first), wanted.begin() + static_cast<std::ptrdiff_t>(last), 1);
        part.lightmaps = readLightmapPart(scene, *out.solution, readout, layout, used, wanted, run.runner, &run.progress);
        if (run.stopped()) return false;
        part.shadowmask = readShadowmaskRecords(*out.solution, layout, wanted, run.runner);
        if (out.options.lightmaps.directional)
            part.directions = readDirectionRecords(*out.solution, readout, layout, wanted, run.runner);
        if (run.stopped()) return false;
    }
    if (out.options.probes) {
        run.beginPhase("probes");
        const std::vector<double> each(out.options.probes->size(), 1.0);
        const auto [probe_begin, probe_end] = shardRange(each, shard, shards);
        part.probe_begin = probe_begin;
        part.probe_end = probe_end;
        part.probes = evaluateProbes(*out.solution, readout, *out.options.probes,
                                     static_cast<double>(out.options.import.unit_scale), run.runner, run.progress,
                                     probe_begin, probe_end);
        if (run.stopped()) return false;
    }
    return true;
}

// The read-out assembled from every shard's part (in shard order, checked), and the bake finished.
void assembleParts(StageRun& run, LightmapLayout* lightmap_layout, const LightmapOptions* lightmap_options,
                   const std::vector<ReadoutPart>& parts) {
    Bake& out = run.out;
    const Scene& scene = *out.scene;
    const SourceLocation where{scene.source_path, 0, 0};
    out.report.options = out.options.solver;
    out.report.solve = parts.front().solve;
    run.beginPhase("merge");
    std::vector<VertexPointLight> vertices;
    for (const ReadoutPart& part : parts) vertices.push_back(part.vertices);
    std::optional<VertexBake> assembled = assembleVertices(scene, vertices);
    const size_t probe_count = out.options.probes ? out.options.probes->size() : 0;
    size_t next_probe = 0;
    for (const ReadoutPart& part : parts) {
        if (part.probe_begin != next_probe || part.probe_end - part.probe_begin != part.probes.size()) break;
        out.probe_irradiance.insert(out.probe_irradiance.end(), part.probes.begin(), part.probes.end());
        next_probe = part.probe_end;
    }
    if (!assembled || next_probe != probe_count || out.probe_irradiance.size() != probe_count) {
        run.diagnostics.error(where, "the parts do not cover the scene's vertices and probes once each "
                                     "(read with other options than the merge's?)");
        return (void)run.stopped();
    }
    out.vertices = std::move(*assembled);
    out.report.vertex_readout = readoutReport(out.vertices.work);
    if (lightmap_layout) {
        LightmapLayout& layout = *lightmap_layout;
        const LightmapOptions& used = *lightmap_options;
        std::vector<LightmapPart> lightmaps;
        for (const ReadoutPart& part : parts) lightmaps.push_back(part.lightmaps);
        std::vector<ShadowmaskRecords> masks;
        std::vector<ChartRecords> directions;
        for (const ReadoutPart& part : parts) {
            masks.push_back(part.shadowmask);
            directions.push_back(part.directions);
        }
        BakedLightmaps baked;
        std::optional<Shadowmask> mask =
            assembleShadowmask(layout, used.padding, masks, scene.source_path, run.diagnostics);
        std::optional<LightmapDirections> rebuilt;
        if (out.options.lightmaps.directional) rebuilt = assembleDirections(layout, used.padding, directions);
        if (!mask || (out.options.lightmaps.directional && !rebuilt) ||
            !assembleLightmaps(scene, std::move(layout), used, lightmaps, run.runner, baked.lightmaps)) {
            run.diagnostics.error(where, "the parts do not cover the scene's lightmap charts once each "
                                         "(read with other options than the merge's?)");
            return (void)run.stopped();
        }
        baked.shadowmask = std::move(*mask);
        if (rebuilt) baked.directions = std::move(*rebuilt);
        completeLightmaps(run, std::move(baked), used, nullptr, readoutOptionsOf(out.options));
    }
    finishStages(run);
}

}  // namespace

std::pair<size_t, size_t> shardRange(const std::vector<double>& costs, uint32_t shard, uint32_t shards) {
    shards = std::max<uint32_t>(shards, 1);
    shard = std::clamp<uint32_t>(shard, 1, shards);
    const double total = std::accumulate(costs.begin(), costs.end(), 0.0);
    // The first item whose cost before it reaches k / N of the total.
    const auto boundary = [&](uint32_t k) {
        if (k == 0) return size_t{0};
        if (k >= shards) return costs.size();
        const double target = total * static_cast<double>(k) / static_cast<double>(shards);
        double before = 0.0;
        for (size_t i = 0; i < costs.size(); ++i) {
            if (before >= target) return i;
            before += costs[i];
        }
        return costs.size();
    };
    return {boundary(shard - 1), boundary(shard)};
}

std::optional<ReadoutPart> gatherShard(const std::string& path, const BakeOptions& options, uint32_t shard,
                                       uint32_t shards, Progress& progress, Diagnostics& diagnostics) {
    ReadoutPart part;
    part.shard = shard;
    part.shards = shards;
    part.scene = path;
    const Stages stages = [&](Bake& out, Progress& p, Diagnostics& d) {
        StageRun run{out, ParallelRunner(out.options.threading, p.cancelFlag()), p, d};
        std::optional<LightmapLayout> layout;
        std::optional<LightmapOptions> used;
        if (!prepareShardStep(run, layout, used)) return;
        const Scene& scene = *out.scene;
        part.solution_key = solutionKey(scene, out.options.solver);
        part.inputs_sha256 = out.inputs_sha256;
        const std::string& file = out.options.solution_file;
        if (!solutionFileHolds(part.solution_key, file)) {
            d.error({file, 0, 0}, "does not hold the solution of " + path +
                                      " for these solver settings (radbake solve with the same options writes it)");
            return (void)run.stopped();
        }
        run.beginPhase("saved solution");
        out.solution = loadSolution(scene, out.options.solver, part.solution_key, file, run.runner.threads(), d);
        if (run.stopped()) return;
        if (!out.solution) {
            d.error({file, 0, 0}, "cannot read the solution");
            return (void)run.stopped();
        }
        part.solve = out.solution->stats;
        if (!readShard(run, layout ? &*layout : nullptr, used ? &*used : nullptr, part)) return;
        p.endPhase();
        out.status = BakeStatus::Ok;
    };
    const Bake done = importAndRun(path, options, progress, diagnostics, stages);
    if (!done.ok()) return std::nullopt;
    return part;
}

void readOutAcrossRanks(StageRun& run, std::optional<LightmapCharts> charts) {
    Bake& out = run.out;
    const Ranks& ranks = run.runner.ranks();
    std::optional<LightmapLayout> layout;
    std::optional<LightmapOptions> used;
    if (charts) {
        used = charts->options;
        layout.emplace();
        if (!packLightmapCharts(std::move(charts->charts), *used, *layout, run.diagnostics) || run.stopped())
            return (void)run.stopped();
    }
    // kShardsPerRank shards a rank, dealt round-robin: the read-out's cost estimates are rough
    // (a lit chart costs more than a dark one of its size), and interleaved shards even out.
    const uint32_t size = static_cast<uint32_t>(ranks.size());
    const uint32_t shards = kShardsPerRank * size;
    Writer mine;
    const auto start = std::chrono::steady_clock::now();
    for (uint32_t shard = static_cast<uint32_t>(ranks.rank()) + 1; shard <= shards; shard += size) {
        ReadoutPart part;
        part.shard = shard;
        part.shards = shards;
        part.solve = out.solution->stats;
        if (!readShard(run, layout ? &*layout : nullptr, used ? &*used : nullptr, part)) return;
        writeString(mine, encodeReadoutPart(part));
    }
    ranks.addSharedSeconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    const std::vector<std::string> bytes = ranks.gatherToLead(mine.bytes);
    if (!ranks.lead()) {
        out.status = BakeStatus::Ok;
        return;
    }
    std::vector<ReadoutPart> parts;
    for (size_t k = 0; k < bytes.size(); ++k) {
        Reader reader{bytes[k]};
        for (uint32_t shard = static_cast<uint32_t>(k) + 1; shard <= shards; shard += size) {
            std::string encoded;
            readString(reader, encoded);
            std::optional<ReadoutPart> decoded =
                decodeReadoutPart(encoded, "the read-out of rank " + std::to_string(k), run.diagnostics);
            if (!decoded) return (void)run.stopped();
            parts.push_back(std::move(*decoded));
        }
    }
    std::sort(parts.begin(), parts.end(), [](const ReadoutPart& a, const ReadoutPart& b) { return a.shard < b.shard; });
    assembleParts(run, layout ? &*layout : nullptr, used ? &*used : nullptr, parts);
}

Bake mergeParts(const std::string& path, const BakeOptions& options, const std::vector<ReadoutPart>& given,
                Progress& progress, Diagnostics& diagnostics) {
    std::vector<ReadoutPart> parts = given;
    std::stable_sort(parts.begin(), parts.end(), [](const ReadoutPart& a, const ReadoutPart& b) { return a.shard < b.shard; });
    const Stages stages = [&](Bake& out, Progress& p, Diagnostics& d) {
        StageRun run{out, ParallelRunner(out.options.threading, p.cancelFlag()), p, d};
        std::optional<LightmapLayout> layout;
        std::optional<LightmapOptions> used;
        if (!prepareShardStep(run, layout, used)) return;
        const Scene& scene = *out.scene;
        if (!checkParts(parts, out.inputs_sha256, solutionKey(scene, out.options.solver), {path, 0, 0}, d))
            return (void)run.stopped();
        assembleParts(run, layout ? &*layout : nullptr, used ? &*used : nullptr, parts);
    };
    return importAndRun(path, options, progress, diagnostics, stages);
}

std::string encodeReadoutPart(const ReadoutPart& part) {
    Writer w;
    w.bytes = kPartMagic;
    w.value(part.shard);
    w.value(part.shards);
    writeString(w, part.arguments);
    writeString(w, part.scene);
    writeString(w, part.inputs_sha256);
    writeString(w, part.solution_key);
    w.value(part.solve);
    w.value(static_cast<uint64_t>(part.vertices.begin));
    w.value(static_cast<uint64_t>(part.vertices.end));
    w.array(part.vertices.groups);
    w.array(part.vertices.h);
    w.value(part.vertices.work);
    const LightmapPart& l = part.lightmaps;
    w.array(l.charts);
    w.array(l.rgb);
    w.array(l.state);
    w.array(l.edge_queries);
    w.array(l.edge_light);
    for (const uint64_t count : {l.covered, l.hidden, l.evaluated, l.interpolated, l.required, l.edge_evaluations})
        w.value(count);
    w.value(l.work);
    w.value(static_cast<uint64_t>(part.shadowmask.names.size()));
    for (const std::string& name : part.shadowmask.names) writeString(w, name);
    for (const ChartRecords* records : {&part.shadowmask.records, &part.directions}) {
        w.array(records->charts);
        w.value(records->size);
        w.array(records->bytes);
    }
    w.value(part.probe_begin);
    w.value(part.probe_end);
    w.array(part.probes);
    return std::move(w.bytes);
}

std::optional<ReadoutPart> decodeReadoutPart(const std::string& bytes, const std::string& where,
                                             Diagnostics& diagnostics) {
    if (bytes.compare(0, sizeof kPartMagic - 1, kPartMagic) != 0) {
        diagnostics.error({where, 0, 0}, "is not a read-out part of this radbake");
        return std::nullopt;
    }
    ReadoutPart part;
    Reader r{bytes, sizeof kPartMagic - 1};
    uint64_t begin = 0, end = 0;
    r.value(part.shard);
    r.value(part.shards);
    readString(r, part.arguments);
    readString(r, part.scene);
    readString(r, part.inputs_sha256);
    readString(r, part.solution_key);
    r.value(part.solve);
    r.value(begin);
    r.value(end);
    r.array(part.vertices.groups);
    r.array(part.vertices.h);
    r.value(part.vertices.work);
    LightmapPart& l = part.lightmaps;
    r.array(l.charts);
    r.array(l.rgb);
    r.array(l.state);
    r.array(l.edge_queries);
    r.array(l.edge_light);
    for (uint64_t* count : {&l.covered, &l.hidden, &l.evaluated, &l.interpolated, &l.required, &l.edge_evaluations})
        r.value(*count);
    r.value(l.work);
    uint64_t names = 0;
    r.value(names);
    for (uint64_t k = 0; k < names && r.ok && k <= bytes.size(); ++k) readString(r, part.shadowmask.names.emplace_back());
    for (ChartRecords* records : {&part.shadowmask.records, &part.directions}) {
        r.array(records->charts);
        r.value(records->size);
        r.array(records->bytes);
    }
    r.value(part.probe_begin);
    r.value(part.probe_end);
    r.array(part.probes);
    part.vertices.begin = begin;
    part.vertices.end = end;
    if (!r.ok || r.at != bytes.size() || part.shard < 1 || part.shard > part.shards) {
        diagnostics.error({where, 0, 0}, "the read-out part is damaged");
        return std::nullopt;
    }
    return part;
}

void stageReadoutPart(const ReadoutPart& part, OutputTransaction& transaction, Diagnostics& diagnostics) {
    writeFileBytes(transaction.stage(kPartFile), encodeReadoutPart(part), diagnostics);
}

std::optional<ReadoutPart> readReadoutPart(const std::filesystem::path& folder, Diagnostics& diagnostics) {
    const std::filesystem::path file = folder / kPartFile;
    std::string why;
    const std::optional<std::string> bytes = readRegularFile(file.string(), why);
    if (!bytes) {
        diagnostics.error({folder.string(), 0, 0}, "is not a read-out part (" + file.filename().string() + ": " + why + ")");
        return std::nullopt;
    }
    std::optional<ReadoutPart> part = decodeReadoutPart(*bytes, file.string(), diagnostics);
    if (part) part->folder = folder.string();
    return part;
}

}  // namespace radbake
