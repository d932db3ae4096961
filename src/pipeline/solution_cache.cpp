// The solution cache (solution_cache.h): a header line, the key, then the solution's arrays
// as raw records (trivially copyable; their sizes are part of the key).
#include "pipeline/solution_cache.h"

#include <fstream>

#include <cstddef>
#include <cstring>
#include <system_error>
#include <type_traits>
#include <vector>

#include "core/binary_records.h"
#include "core/memory.h"
#include "core/regular_file.h"
#include "export/hash.h"
#include "export/output_transaction.h"
#include "pipeline/bake_options.h"
#include "visibility/ray_caster.h"

namespace radbake {
namespace {

constexpr char kMagic[] = "radbake solution 2\n";

// Every field that changes the solve, one by one (never a struct's padding).
struct KeyWriter {
    std::string bytes;
    template <class T>
    void add(const T& v) {
        static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
        bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    void add(const Vec3& v) { add(v.x), add(v.y), add(v.z); }
    template <class T>
    void addAll(const std::vector<T>& v) {
        add(static_cast<uint64_t>(v.size()));
        for (const T& x : v) add(x);
    }
    void add(const UVec3& v) { add(v.x), add(v.y), add(v.z); }
};

}  // namespace

std::string solutionKey(const Scene& scene, const SolverOptions& o) {
    KeyWriter k;
    k.bytes = radbakeGenerator() + "\n";
    for (const size_t size : {sizeof(Element), sizeof(Link), sizeof(Cluster), sizeof(ClusterLink), sizeof(SolveStats),
                              sizeof(Solution::cluster_kernel[0])})
        k.add(static_cast<uint64_t>(size));
    k.add(static_cast<uint64_t>(scene.meshes.size()));
    for (const Mesh& m : scene.meshes) {
        k.addAll(m.positions);
        k.addAll(m.triangles);
        k.addAll(m.triangle_polygon);
        k.addAll(m.polygon_reflectance);
        k.addAll(m.polygon_emission);
        k.add(m.polygon_count), k.add(m.material), k.add(m.solid), k.add(m.convex_solid);
        // Which meshes are each other's sides (only where there are twins: one-sided keys keep their bytes).
        if (m.twin != kNoMesh) k.add(m.twin), k.add(m.back);
    }
    k.add(static_cast<uint64_t>(scene.materials.size()));
    for (const Material& m : scene.materials) k.add(m.reflectance), k.add(m.emission);
    k.add(static_cast<uint64_t>(scene.lights.size()));
    for (const Light& l : scene.lights) {
        k.add(l.type), k.add(l.position), k.add(l.direction), k.add(l.color), k.add(l.intensity);
        k.add(l.attenuation), k.add(l.radius), k.add(l.beam_width), k.add(l.cut_off_angle), k.add(l.on);
        k.add(l.scoped), k.addAll(l.scope);
        if (l.angular_diameter != 0.0f) k.add(l.angular_diameter);  // only where set: other keys keep their bytes
    }
    if (scene.sky.model != SkyModel::None) {
        k.add(scene.sky.model), k.add(scene.sky.radiance), k.add(scene.sky.up);
        if (scene.sky.model == SkyModel::Background) {
            const BackgroundSky& b = scene.sky.background;
            k.addAll(b.sky_angle), k.addAll(b.sky_color), k.addAll(b.ground_angle), k.addAll(b.ground_color);
        }
        if (scene.sky.model == SkyModel::Map && scene.sky.map)
            k.add(scene.sky.map->width), k.add(scene.sky.map->height), k.addAll(scene.sky.map->rgb);
        k.add(o.sky.grid), k.add(o.sky.depth), k.add(o.sky.search);
    }
    // Every solver knob but max_memory_mb (a budget stops a solve, it does not change it); the
    // read-out's knobs (ReadoutOptions) are not the solver's, so changing them reuses the solution.
    k.add(o.visibility), k.add(o.quality), k.add(o.error_threshold), k.add(o.min_element_area);
    k.add(o.iteration_tolerance), k.add(o.max_iterations), k.add(o.refine_rounds), k.add(o.quadrature_order);
    k.add(o.quadrature_near_ratio), k.add(o.quadrature_max_depth), k.add(o.visibility_samples);
    k.add(o.area_exponent), k.add(o.clustering), k.add(o.local_error_threshold), k.add(o.keep_blocked_links);
    return sha256Hex(k.bytes);
}

bool saveSolution(const Solution& s, const std::string& key, const std::filesystem::path& file,
                  Diagnostics& diagnostics) {
    // Written from the solution's own memory: a serialised copy was as large again (1.7 GB on
    // a million-triangle building).
    const std::string header = std::string(kMagic) + key + "\n";
    PieceWriter w;
    w.pieces.emplace_back(header);
    w.array(s.vertices);
    w.array(s.vertex_sky);
    w.array(s.elements);
    w.value(s.root_count);
    w.array(s.links);
    w.array(s.clusters);
    w.array(s.cluster_members);
    w.array(s.member_position);
    w.array(s.root_leaf_cluster);
    w.array(s.cluster_links);
    w.array(s.cluster_kernel);
    w.value(s.scene_extent);
    w.value(s.total_area);
    // The stats as they are, padding included (zero: Solution's constructor); but the budget,
    // this machine's memory rather than the solution's, is written as 0, so a solve writes the
    // same bytes on any machine (a loaded solution takes the loading run's budget).
    SolveStats stats;
    std::memcpy(static_cast<void*>(&stats), &s.stats, sizeof stats);
    const double no_budget = 0.0;
    std::memcpy(reinterpret_cast<char*>(&stats) + offsetof(SolveStats, memory_budget_mb), &no_budget, sizeof no_budget);
    w.value(stats);
    const std::string why = replaceRegularFile(file, w.pieces);
    if (why.empty()) return true;
    diagnostics.warning({file.string(), 0, 0}, "could not write the solution cache: " + why);
    return false;
}

namespace {

// The solution's arrays after the header, nullopt when they do not fill `bytes` exactly.
std::optional<Solution> parseSolution(const std::string& bytes, size_t header_size) {
    Solution s;
    Reader r{bytes, header_size};
    r.array(s.vertices);
    r.array(s.vertex_sky);
    r.array(s.elements);
    r.value(s.root_count);
    r.array(s.links);
    r.array(s.clusters);
    r.array(s.cluster_members);
    r.array(s.member_position);
    r.array(s.root_leaf_cluster);
    r.array(s.cluster_links);
    r.array(s.cluster_kernel);
    r.value(s.scene_extent);
    r.value(s.total_area);
    r.value(s.stats);
    if (!r.ok || r.at != bytes.size() || s.root_count > s.elements.size()) return std::nullopt;
    return s;
}

}  // namespace

bool solutionFileHolds(const std::string& key, const std::filesystem::path& file) {
    std::string why;
    const std::optional<std::string> bytes = readRegularFile(file.string(), why);
    const std::string header = std::string(kMagic) + key + "\n";
    return bytes && bytes->compare(0, header.size(), header) == 0 && parseSolution(*bytes, header.size());
}

namespace {

// The saved solution's bytes when `file` holds one under `key`; empty otherwise (a note or an
// error says why, as loadSolution's comment tells).
std::string readSavedSolution(const std::string& key, const std::filesystem::path& file, Diagnostics& diagnostics) {
    // Refused before the solve, as it would be replaced after it.
    if (const std::string why = whyNotReplaceable(file.string()); !why.empty()) {
        diagnostics.error({file.string(), 0, 0}, "cannot use the solution file: " + why);
        return {};
    }
    std::string why;
    std::optional<std::string> read = readRegularFile(file.string(), why);
    if (!read) {  // absent: solve and save it, without a word
        std::error_code ec;
        if (std::filesystem::exists(file, ec))
            diagnostics.note({file.string(), 0, 0}, "cannot read the saved solution (" + why + "): solving again");
        return {};
    }
    const std::string header = std::string(kMagic) + key + "\n";
    if (read->compare(0, header.size(), header) != 0) {
        diagnostics.note({file.string(), 0, 0}, "the saved solution is for another scene or other solver settings: solving again");
        return {};
    }
    if (!parseSolution(*read, header.size())) {
        diagnostics.note({file.string(), 0, 0}, "the saved solution is damaged: solving again");
        return {};
    }
    return std::move(*read);
}

}  // namespace

std::optional<Solution> loadSolution(const Scene& scene, const SolverOptions& options, const std::string& key,
                                     const std::filesystem::path& file, int threads, Diagnostics& diagnostics,
                                     const Ranks& ranks) {
    // The lead reads the file: the other ranks may run where it is not.
    std::string bytes = ranks.lead() ? readSavedSolution(key, file, diagnostics) : std::string();
    ranks.broadcast(bytes);
    if (bytes.empty()) return std::nullopt;
    std::optional<Solution> parsed = parseSolution(bytes, std::string(kMagic).size() + key.size() + 1);
    if (!parsed) return std::nullopt;
    Solution s = std::move(*parsed);
    s.scene = &scene;
    s.options = options;
    s.stats.memory_budget_mb = memoryBudgetMegabytes(options.max_memory_mb);
    if (s.root_count > 0) {
        s.rays = RayCaster::build(scene, diagnostics, threads);
        if (!s.rays) return std::nullopt;
    }
    return s;
}

}  // namespace radbake
