#pragma once
// A bake split over machines (issue 29): after `radbake solve`, each of N read-out shards reads
// the light of its share of the scene from the saved solution (`radbake gather --shard K/N`),
// and `radbake merge` assembles the parts into exactly the outputs one `radbake bake` writes.
// A shard takes a contiguous run of the scene's welded vertex points, of its lightmap charts
// and of its probes, each balanced by estimated cost; every point's light is its own and each
// chart's texels are too, so the split changes no byte.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "export/output_transaction.h"
#include "pipeline/bake.h"
#include "bake/lightmap_directions.h"
#include "bake/shadowmask.h"
#include "readout/vertex_bake.h"

namespace radbake {

// What one shard read, and what it was read from.
struct ReadoutPart {
    uint32_t shard = 1, shards = 1;  // K of N, from 1
    std::string arguments;           // the step's options as its program gave them (opaque here: merge's caller parses them again)
    std::string scene;               // the scene path as the step was given it
    std::string inputs_sha256;       // of every file the scene read (Bake::inputs_sha256)
    std::string solution_key;        // of the solution read (solution_cache.h)
    SolveStats solve;
    VertexPointLight vertices;
    LightmapPart lightmaps;          // of its charts (none without lightmaps)
    ShadowmaskRecords shadowmask;    // of its charts, with real-time lights
    ChartRecords directions;         // of its charts, with --directional
    uint64_t probe_begin = 0, probe_end = 0;
    std::vector<DVec3> probes;       // H (W/m^2) of probes [probe_begin, probe_end)
    std::string folder;              // where it was read from (for messages; not saved)
};

// [begin, end) of shard `shard` of `shards` over items of the given costs, contiguous and in
// order; every item is in exactly one shard.
std::pair<size_t, size_t> shardRange(const std::vector<double>& costs, uint32_t shard, uint32_t shards);

// Shard `shard` of `shards` of the read-out of the scene at `path`, from the solution in
// options.solution_file, which must hold that scene's solution for options.solver (else a
// located error: `radbake solve` with the same options writes it). nullopt after reporting.
std::optional<ReadoutPart> gatherShard(const std::string& path, const BakeOptions& options, uint32_t shard,
                                       uint32_t shards, Progress& progress, Diagnostics& diagnostics);

// The bake `bake(path, options)` makes, assembled from parts of every shard 1..N, each once: a
// missing, repeated or foreign part (another scene's files, another solution, another shard
// count) is an error naming it. The status says whether it worked.
Bake mergeParts(const std::string& path, const BakeOptions& options, const std::vector<ReadoutPart>& parts,
                Progress& progress, Diagnostics& diagnostics);

// A part's file in its folder, staged into `transaction`; and read back (nullopt after a
// located error: absent, not a part, damaged).
inline constexpr char kPartFile[] = "readout.part";
std::string encodeReadoutPart(const ReadoutPart& part);
// nullopt after an error located at `where` (not a part, damaged).
std::optional<ReadoutPart> decodeReadoutPart(const std::string& bytes, const std::string& where,
                                             Diagnostics& diagnostics);
void stageReadoutPart(const ReadoutPart& part, OutputTransaction& transaction, Diagnostics& diagnostics);
std::optional<ReadoutPart> readReadoutPart(const std::filesystem::path& folder, Diagnostics& diagnostics);

}  // namespace radbake
