#pragma once
// radbake, the library: the whole pipeline on one screen (DESIGN.md section 3). Each stage is
// a free function from plain data to plain data; bake() runs them all in memory and
// writeBake() writes the result, all or nothing. `radbake bake` is these two calls.
//
// Link it from another project:   find_package(radbake REQUIRED)
//                                 target_link_libraries(tool PRIVATE radbake::radbake)
// and see examples/bake_scene/. Errors are never thrown: every stage reports located errors
// to a Diagnostics and returns an empty result or false. Every stage that runs in parallel
// takes a ParallelRunner (its threads; the cancel flag of a Progress).
#include <filesystem>
#include <optional>
#include <string>

#include "bake/lightmap_bake.h"    // Lightmaps, LightmapCharts, LightmapOptions
#include "bake/lightmap_budget.h"  // LightmapBudget
#include "core/diagnostics.h"      // Diagnostics, SourceLocation
#include "core/parallel.h"         // Threading, ParallelRunner
#include "core/progress.h"         // Progress, ProgressEvent
#include "geometry/parts.h"        // PartSet, PartOptions
#include "io/import.h"             // ImportOptions
#include "pipeline/bake.h"         // Bake, BakeStatus, BakedLightmaps
#include "pipeline/bake_options.h" // BakeOptions, LightmapSettings
#include "pipeline/depfile.h"      // writeDepfile
#include "pipeline/lightmap_scales.h" // LightmapScaleRule, readLightmapScales
#include "radiosity/solution.h"    // Solution, Element, Link
#include "radiosity/solver.h"      // SolverOptions, SolveStats (solver_options.h)
#include "readout/evaluate_probe.h" // probeIrradiance
#include "readout/readout_options.h" // ReadoutOptions, GatherMode, EdgeCorrection
#include "readout/reconstruct.h"   // LinkReconstruction
#include "readout/vertex_bake.h"   // VertexBake
#include "scene/creases.h"         // splitHardEdges
#include "scene/scene.h"           // Scene, Mesh, Material, Light, Camera
#include "scene/two_sided.h"       // addBackTwins, frontMesh

namespace radbake {

// 1. Any supported file (VRML97, VRML 1.0, X3D classic, everything Assimp reads) -> a
//    validated Scene in metres, its vertices split at hard edges (scene/creases.h:
//    splitHardEdges, which a Scene built in memory can call too).
std::optional<Scene> importScene(const std::string& path, const ImportOptions& options, Diagnostics& diagnostics);

// 1b. Two-sided surfaces (scene/two_sided.h): every mesh that is not `solid` gets a back
//     twin, a mesh of its own with its own light, except a closed one with nothing lit inside
//     (its backs are dark: baked one-sided, counted as closed_two_sided). bake() does it; a
//     caller running the stages one by one calls it after importScene. Returns how many twins
//     it added.
size_t addBackTwins(Scene& scene);

// 2. Convex parts with their AABBs and OBBs: the potential occluders of every shaft.
PartSet buildParts(const Scene& scene, const PartOptions& options, Diagnostics& diagnostics);

// 3. Hierarchical radiosity: elements, links (shafts, occlusion tests, rays), the solve.
std::optional<Solution> solveRadiosity(const Scene& scene, const PartSet& parts, const SolverOptions& options,
                                       ParallelRunner& runner, Progress& progress, Diagnostics& diagnostics);

// 4. The read-out: the light at any point read from a solution (readout/), as its
//    ReadoutOptions say (ReadoutOptions::forQuality; none of them changes the solution).
//    Probes: probeIrradiance (the exhaustive gather). Points on the scene's surfaces:
//    LinkReconstruction (through the links that reach the point's leaf). Vertices: H / pi at
//    every vertex of every mesh.
VertexBake bakeVertices(const Scene& scene, const Solution& solution, const ReadoutOptions& options,
                        ParallelRunner& runner, Progress* progress /* = nullptr */);

// 5. Lightmaps: charts (within the texel budget, before the solve), then packing, texels,
//    dilation and seams.
std::optional<LightmapCharts> chartLightmapsWithinBudget(const Scene& scene, LightmapOptions options,
                                                         const LightmapBudget& budget, Diagnostics& diagnostics);
bool bakeLightmaps(const Scene& scene, const Solution& solution, const ReadoutOptions& readout, LightmapCharts charts,
                   ParallelRunner& runner, Lightmaps& lightmaps, Diagnostics& diagnostics,
                   Progress* progress /* = nullptr */);

// All of the above (plus probes and previews), in memory.
Bake bake(const std::string& path, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics);
Bake bake(Scene scene, const BakeOptions& options, Progress& progress, Diagnostics& diagnostics);

// 6. glb, PLY, EXR atlases, probes.csv, previews, stats.json, manifest.json: all or nothing,
//    touching only what this bake and the folder's last one wrote (its manifest).
bool writeBake(const Bake& bake, const std::filesystem::path& out_dir, Diagnostics& diagnostics,
               WrittenBake* written /* = nullptr */);
// The folder locked before the bake, so a second bake into it is refused before any work:
// OutputTransaction::begin(), claimOutputFolder(), bake(), commitBake(bake, transaction); or
// all of it in one call, bakeInto().
bool commitBake(const Bake& bake, OutputTransaction& transaction, Diagnostics& diagnostics,
                WrittenBake* written /* = nullptr */);
bool bakeInto(const std::string& path, const std::filesystem::path& out_dir, const BakeOptions& options,
              Progress& progress, Diagnostics& diagnostics, Bake* result /* = nullptr */,
              WrittenBake* written /* = nullptr */);

}  // namespace radbake
