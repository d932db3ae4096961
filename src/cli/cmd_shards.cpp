// `radbake gather` and `radbake merge`: a bake's read-out split into shards (pipeline/shards.h).
//   radbake solve  SCENE --solution S [options]
//   radbake gather SCENE --solution S --shard K/N -o PART_K [options]     (K = 1..N, any machine)
//   radbake merge  PART_1 ... PART_N -o OUT                                 (= radbake bake SCENE -o OUT [options])
// A part records the options it was gathered with (those that change outputs, as CLI11 writes a
// config) and merge parses them again with the same parser, so every step shares one command line.
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli/bake_args.h"
#include "cli/commands.h"
#include "cli/option_checks.h"
#include "export/output_transaction.h"
#include "pipeline/shards.h"
#include "radbake.h"

namespace radbake::cli {
namespace {

// Not recorded in a part, nor compared between parts: options that change no output byte, the
// scene (recorded on its own) and the solution file (its key is: the path may differ between
// machines).
const std::vector<std::string> kNotRecorded = {"scene",   "output", "shard",          "threads",
                                               "quiet",   "depfile", "no-pin-threads", "solution"};

// The gather's options as a CLI11 config, without the run-only ones.
std::string recordedOptions(const CLI::App& cmd) {
    std::istringstream config(cmd.config_to_str(false, false));
    std::string kept;
    for (std::string line; std::getline(config, line);) {
        const std::string key = line.substr(0, line.find('='));
        bool run_only = false;
        for (const std::string& name : kNotRecorded) run_only = run_only || key == name;
        if (!run_only && !line.empty()) kept += line + "\n";
    }
    return kept;
}

struct GatherArgs {
    BakeArgs bake;
    std::string shard;  // "K/N"
    uint32_t k = 0, n = 0;
    std::string recorded;
};

// K and N of "K/N", 1 <= K <= N <= 100000; false when the text is not that.
bool parseShard(const std::string& text, uint32_t& k, uint32_t& n) {
    unsigned long a = 0, b = 0;
    char slash = 0, extra = 0;
    std::istringstream in(text);
    if (!(in >> a >> slash >> b) || slash != '/' || (in >> extra)) return false;
    if (a < 1 || b < 1 || a > b || b > 100000) return false;
    k = static_cast<uint32_t>(a);
    n = static_cast<uint32_t>(b);
    return text.find_first_not_of("0123456789/") == std::string::npos;
}

int runGather(const GatherArgs& args) {
    stepRanks("gather", false);
    Progress progress(progressStyleOf(args.bake.quiet));
    Diagnostics diagnostics;
    routeDiagnostics(diagnostics, progress);
    cleanUpStagingOnSignals();
    if (!depfileWritable(args.bake, diagnostics)) return kExitInputError;
    OutputTransaction transaction(args.bake.out_dir);
    if (!transaction.begin(diagnostics)) return kExitInputError;
    BakeOptions options = bakeOptions(args.bake);
    if (!readBakeSideFiles(args.bake, options, diagnostics)) return kExitInputError;
    std::optional<ReadoutPart> part = gatherShard(args.bake.scene, options, args.k, args.n, progress, diagnostics);
    if (!part) return kExitInputError;
    part->arguments = args.recorded;
    stageReadoutPart(*part, transaction, diagnostics);
    if (diagnostics.hasErrors() || !transaction.commit(diagnostics)) return kExitInputError;
    const std::string part_file = (std::filesystem::path(args.bake.out_dir) / kPartFile).lexically_normal().string();
    if (!args.bake.depfile.empty()) {
        std::vector<std::string> inputs = {args.bake.scene, args.bake.solution_file};
        for (const std::string* side : {&args.bake.probes, &args.bake.lightmap_scales, &args.bake.realtime_lights})
            if (!side->empty()) inputs.push_back(*side);
        if (!writeDepfile(args.bake.depfile, {part_file}, inputs, diagnostics)) return kExitInputError;
    }
    std::printf("radbake: gathered shard %u of %u of %s in %.2f s: %zu of its vertex points, %zu probes -> %s\n",
                args.k, args.n, args.bake.scene.c_str(), progress.totalSeconds(),
                static_cast<size_t>(part->vertices.end - part->vertices.begin), part->probes.size(), part_file.c_str());
    return kExitOk;
}

struct MergeArgs {
    std::vector<std::string> parts;
    std::string out_dir;
    std::string depfile;
    int threads = 0;
    bool no_pin_threads = false;
    bool quiet = false;
};

int runMerge(const MergeArgs& args) {
    Diagnostics diagnostics;
    printDiagnosticsToStderr(diagnostics);
    std::vector<ReadoutPart> parts;
    for (const std::string& folder : args.parts)
        if (std::optional<ReadoutPart> part = readReadoutPart(folder, diagnostics)) parts.push_back(std::move(*part));
    if (diagnostics.hasErrors()) return kExitInputError;
    if (parts.empty()) return kExitUsage;
    // One read-out: every part gathered from one scene with one command line.
    for (const ReadoutPart& part : parts)
        if (part.scene != parts.front().scene || part.arguments != parts.front().arguments) {
            diagnostics.error({part.folder, 0, 0}, "was gathered with another scene or other options than " +
                                                       parts.front().folder);
            return kExitInputError;
        }
    BakeArgs bake;
    CLI::App parser;
    parser.allow_config_extras(false);
    addBakeOptions(parser, bake);
    try {
        std::istringstream recorded(parts.front().arguments);
        parser.parse_from_stream(recorded);
    } catch (const CLI::Error& e) {
        diagnostics.error({parts.front().folder, 0, 0}, std::string("cannot read the options it was gathered with: ") + e.what());
        return kExitInputError;
    }
    bake.scene = parts.front().scene;
    bake.out_dir = args.out_dir;
    bake.depfile = args.depfile;
    bake.threads = args.threads;
    bake.no_pin_threads = args.no_pin_threads;
    bake.quiet = args.quiet;
    std::vector<std::string> part_files;
    for (const std::string& folder : args.parts)
        part_files.push_back((std::filesystem::path(folder) / kPartFile).lexically_normal().string());
    return runBakeInto(
        bake, stepRanks("merge", false),
        [&](const BakeOptions& options, Progress& progress, Diagnostics& d) {
            return mergeParts(bake.scene, options, parts, progress, d);
        },
        part_files);
}

}  // namespace

void addShardCommands(CLI::App& app, int& result) {
    auto gather = std::make_shared<GatherArgs>();
    CLI::App* cmd = app.add_subcommand(
        "gather", "Read shard K of N of a bake's light from a solution file into a part folder (after radbake solve)");
    cmd->add_option("scene", gather->bake.scene, "Scene file (VRML97, VRML 1.0, or any format Assimp reads)")->required();
    cmd->add_option("-o,--output", gather->bake.out_dir, "The part folder to write")->check(nonEmptyPath())->required();
    cmd->add_option("--shard", gather->shard, "K/N: this shard's number K (from 1) of N")->required();
    addBakeOptions(*cmd, gather->bake);
    cmd->get_option("--solution")->required();
    cmd->callback([gather, cmd, &result] {
        if (!parseShard(gather->shard, gather->k, gather->n)) {
            std::fprintf(stderr, "--shard: '%s' is not K/N with 1 <= K <= N <= 100000\n", gather->shard.c_str());
            result = kExitUsage;
            return;
        }
        gather->recorded = recordedOptions(*cmd);
        runGuarded(gather->bake.scene, "gathering", result, [&] { return runGather(*gather); });
    });

    auto merge = std::make_shared<MergeArgs>();
    CLI::App* m = app.add_subcommand(
        "merge", "Assemble the parts of every shard into the outputs one radbake bake writes (same options)");
    m->add_option("parts", merge->parts, "Part folders written by radbake gather, one per shard")->required();
    m->add_option("-o,--output", merge->out_dir, "Output directory")->check(nonEmptyPath())->default_str("baked/<scene name>/");
    m->add_option("--depfile", merge->depfile, "Also write a Make-syntax depfile: every output, then every file read")
        ->check(nonEmptyPath());
    m->add_option("--threads", merge->threads, "Worker threads; 0: all cores")
        ->transform(wholeIn(0, 1024))
        ->capture_default_str();
    m->add_flag("--no-pin-threads", merge->no_pin_threads, "Leave worker threads unpinned");
    m->add_flag("-q,--quiet", merge->quiet, "Print only warnings, errors and a one-line summary");
    m->callback([merge, &result] {
        runGuarded(merge->parts.empty() ? std::string() : merge->parts.front(), "merging", result,
                   [&] { return runMerge(*merge); });
    });
}

}  // namespace radbake::cli
