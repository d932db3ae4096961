// lightmap_at_vertices: what an engine shows at each vertex of a lightmapped bake, as probe
// values, for the per-vertex accuracy yardstick (issue 13's lightmap target).
//
//   lightmap_at_vertices BAKE_DIR PROBES_FILE OUT.csv [--skip-missing]
//
// BAKE_DIR is a `radbake bake SCENE -o BAKE_DIR` folder with lightmaps (its one .glb, and the
// EXR atlases its primitives name in extras.radbake_lightmap); PROBES_FILE a probe file, as
// tools/vertex_probes writes one per vertex (nudged 1e-4 of the diagonal into its own face).
// For each probe: the output vertex with the probe's normal (dot > 0.999) nearest to it (grid
// cells of 1e-3 of the glb's diagonal, as tools/vertex_error.py's vertex_rows does on the
// .ply), its atlas sampled at its TEXCOORD_1 as a GPU samples with linear filtering and
// clamp-to-edge, times pi (the atlas holds H / pi). OUT.csv is probes.csv's format
// (x,y,z,nx,ny,nz,r,g,b: the probe as given, %.9g, and H), so that
//   python3 tools/vertex_error.py OUT.csv REFERENCE.csv --probes PROBES_FILE
// scores the lightmap where tools/vertex_error.py --vertices scores the vertex bake.
// On stderr: how far the lookups are from the matched vertices' own baked value
// (_RADBAKE_LIGHT), the worst of them, and how far apart the lookups of coincident vertices
// (split at chart seams) are. Exit 1 on bad input (no glb, a probe without a vertex, a vertex
// whose mesh has no lightmap chart, an unreadable atlas), 2 on a bad command line. With
// --skip-missing a probe without an output vertex of its normal (a scene whose smooth normals
// are split at hard edges) is counted on stderr and written as 0 instead, for diagnosis only.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "export/compare_load.h"
#include "export/probes.h"

namespace {

using namespace radbake;
namespace fs = std::filesystem;

// GL's LINEAR filter with CLAMP_TO_EDGE (OpenGL 4.6 section 8.14.2): texel centres at
// (i + 0.5) / width, v down from the top row as glTF's UVs and the EXR have it. Written
// out here rather than reusing the bake's own bilinearLookup, so that a convention the bake
// got wrong shows up in the measurement instead of cancelling out.
DVec3 sampleLinearClamp(const RgbImage& image, DVec2 uv) {
    const double x = uv.x * image.width - 0.5, y = uv.y * image.height - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    DVec3 sum(0.0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const int i = std::clamp(static_cast<int>(x0) + dx, 0, image.width - 1);
            const int j = std::clamp(static_cast<int>(y0) + dy, 0, image.height - 1);
            const float* t = &image.rgb[3 * (static_cast<size_t>(j) * image.width + i)];
            sum += (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy) * DVec3(t[0], t[1], t[2]);
        }
    return sum;
}

double grey(const DVec3& v) { return (v.x + v.y + v.z) / 3.0; }

struct VertexRef {
    uint32_t block, index;
};

std::string describe(const DVec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "%.6g %.6g %.6g", v.x, v.y, v.z);
    return text;
}

int run(const fs::path& bake_dir, const std::string& probes_path, const fs::path& out_path, bool skip_missing) {
    std::vector<fs::path> glbs;
    if (!fs::is_directory(bake_dir)) throw std::runtime_error(bake_dir.string() + ": not a bake folder");
    for (const auto& entry : fs::directory_iterator(bake_dir))
        if (entry.path().extension() == ".glb") glbs.push_back(entry.path());
    if (glbs.size() != 1)
        throw std::runtime_error(bake_dir.string() + ": expected one .glb, found " + std::to_string(glbs.size()));
    const MeshFile glb = loadGlbFile(glbs[0]);

    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) {
        if (d.severity != Severity::Note) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
    };
    const std::optional<std::vector<Probe>> probes = readProbes(probes_path, diagnostics);
    if (!probes) return 1;
    if (probes->empty()) throw std::runtime_error(probes_path + ": no probes");

    DVec3 lo(INFINITY), hi(-INFINITY);
    for (const VertexBlock& b : glb.blocks) {
        if (b.normals.size() != 3 * b.count) throw std::runtime_error(glbs[0].string() + ": " + b.name + " has no NORMAL");
        for (size_t i = 0; i < b.count; ++i) {
            const DVec3 p(b.positions[3 * i], b.positions[3 * i + 1], b.positions[3 * i + 2]);
            lo = glm::min(lo, p), hi = glm::max(hi, p);
        }
    }
    if (!(lo.x <= hi.x)) throw std::runtime_error(glbs[0].string() + ": no vertices");
    // The probes are 1e-4 of the diagonal from their vertex: well inside a cell and its neighbours.
    const double cell = std::max(1e-12, 1e-3 * glm::length(hi - lo));
    const auto key = [&](const DVec3& p) {
        const DVec3 k = glm::floor(p / cell);
        return std::array<int64_t, 3>{int64_t(k.x), int64_t(k.y), int64_t(k.z)};
    };
    const auto position = [&](VertexRef v) {
        const double* p = &glb.blocks[v.block].positions[3 * v.index];
        return DVec3(p[0], p[1], p[2]);
    };
    std::map<std::array<int64_t, 3>, std::vector<VertexRef>> grid;
    for (uint32_t b = 0; b < glb.blocks.size(); ++b)
        for (uint32_t i = 0; i < glb.blocks[b].count; ++i) grid[key(position({b, i}))].push_back({b, i});

    std::map<std::string, RgbImage> atlases;  // by the name in extras.radbake_lightmap
    const auto lookup = [&](VertexRef v, const Probe& probe) {
        const VertexBlock& b = glb.blocks[v.block];
        if (b.lightmap.empty() || b.uv1.size() != 2 * b.count)
            throw std::runtime_error(glbs[0].string() + ": " + b.name + " has no lightmap chart (probe at " +
                                     probes_path + ":" + std::to_string(probe.location.line) + ")");
        auto it = atlases.find(b.lightmap);
        if (it == atlases.end()) {
            RgbImage image = loadExrFile(bake_dir / b.lightmap);
            if (image.width <= 0 || image.height <= 0 || image.rgb.size() != 3 * size_t(image.width) * image.height)
                throw std::runtime_error((bake_dir / b.lightmap).string() + ": empty atlas");
            it = atlases.emplace(b.lightmap, std::move(image)).first;
        }
        return sampleLinearClamp(it->second, DVec2(b.uv1[2 * v.index], b.uv1[2 * v.index + 1]));
    };

    struct Row {
        size_t probe;
        VertexRef vertex;
        DVec3 lookup, vertex_bake;
    };
    std::vector<Row> rows;
    std::vector<DVec3> irradiance;
    size_t tied = 0;
    double worst_tie = 0.0;
    size_t worst_tie_probe = 0;
    size_t missing = 0, first_missing = 0;
    for (size_t p = 0; p < probes->size(); ++p) {
        const Probe& probe = (*probes)[p];
        const auto k = key(probe.position);
        std::vector<std::pair<double, VertexRef>> found;  // (distance, vertex) with the probe's normal
        for (int64_t dx = -1; dx <= 1; ++dx)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dz = -1; dz <= 1; ++dz) {
                    const auto cell_it = grid.find({k[0] + dx, k[1] + dy, k[2] + dz});
                    if (cell_it == grid.end()) continue;
                    for (VertexRef v : cell_it->second) {
                        const double* n = &glb.blocks[v.block].normals[3 * v.index];
                        if (glm::dot(DVec3(n[0], n[1], n[2]), probe.normal) <= 0.999) continue;
                        found.push_back({glm::length(position(v) - probe.position), v});
                    }
                }
        if (found.empty()) {
            if (!skip_missing)
                throw std::runtime_error(probes_path + ":" + std::to_string(probe.location.line) +
                                         ": no output vertex with normal " + describe(probe.normal) + " near " +
                                         describe(probe.position));
            if (missing++ == 0) first_missing = p;
            irradiance.push_back(DVec3(0.0));
            continue;
        }
        // Nearest, then file order: vertices split at a chart seam share a position exactly.
        std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        const VertexRef v = found[0].second;
        const VertexBlock& b = glb.blocks[v.block];
        const DVec3 value = lookup(v, probe);
        // The other charts' copies of this vertex: an engine shows each on its own triangles.
        for (size_t c = 1; c < found.size() && found[c].first <= found[0].first + 1e-6 * cell; ++c) {
            if (glb.blocks[found[c].second.block].lightmap.empty()) continue;
            const double gap = std::fabs(grey(lookup(found[c].second, probe)) - grey(value)) /
                               std::max(grey(value), 1e-30);
            if (c == 1) ++tied;
            if (gap > worst_tie) worst_tie = gap, worst_tie_probe = p;
        }
        DVec3 vertex_bake(0.0);
        if (b.light.size() == 3 * b.count)
            vertex_bake = DVec3(b.light[3 * v.index], b.light[3 * v.index + 1], b.light[3 * v.index + 2]);
        rows.push_back({p, v, value, vertex_bake});
        irradiance.push_back(kPi * value);
    }
    if (rows.empty())
        throw std::runtime_error(probes_path + ": no probe has an output vertex with its normal near it");
    if (missing)
        std::fprintf(stderr,
                     "lightmap_at_vertices: %zu probes have no output vertex with their normal near them (0 written "
                     "for them; the first at %s:%d, normal %s)\n",
                     missing, probes_path.c_str(), (*probes)[first_missing].location.line,
                     describe((*probes)[first_missing].normal).c_str());
    if (!writeProbesCsv(out_path, *probes, irradiance, diagnostics)) return 1;

    // Against the vertex bake at the same vertices, over those above 1 % of the median
    // (vertex_error.py's --lit median), so dark corners do not dominate.
    std::vector<double> greys;
    for (const Row& r : rows) greys.push_back(grey(r.vertex_bake));
    std::nth_element(greys.begin(), greys.begin() + greys.size() / 2, greys.end());
    const double floor = 0.01 * greys[greys.size() / 2];
    std::vector<std::pair<double, size_t>> gaps;  // (relative gap, row)
    double sum2 = 0.0;
    for (size_t i = 0; i < rows.size(); ++i) {
        const double vb = grey(rows[i].vertex_bake);
        if (!(vb > floor)) continue;
        const double e = (grey(rows[i].lookup) - vb) / vb;
        gaps.push_back({e, i});
        sum2 += e * e;
    }
    std::sort(gaps.begin(), gaps.end(), [](const auto& a, const auto& b) { return std::fabs(a.first) > std::fabs(b.first); });
    const size_t over = std::count_if(gaps.begin(), gaps.end(), [](const auto& g) { return std::fabs(g.first) > 0.05; });
    std::fprintf(stderr,
                 "lightmap_at_vertices: %zu probes, %zu atlases; lookup against the vertex bake (_RADBAKE_LIGHT) "
                 "over %zu vertices above 1 %% of the median: rms %.2f %%, max %.2f %%, %zu beyond 5 %%\n",
                 rows.size(), atlases.size(), gaps.size(), gaps.empty() ? 0.0 : 100.0 * std::sqrt(sum2 / gaps.size()),
                 gaps.empty() ? 0.0 : 100.0 * std::fabs(gaps[0].first), over);
    for (size_t g = 0; g < std::min<size_t>(5, gaps.size()); ++g) {
        const Row& r = rows[gaps[g].second];
        const VertexBlock& b = glb.blocks[r.vertex.block];
        std::fprintf(stderr, "  %+7.2f %%  %s:%d  %s vertex %u (%s) uv1 %.6f %.6f  lookup %.5g  vertex %.5g\n",
                     100.0 * gaps[g].first, probes_path.c_str(), (*probes)[r.probe].location.line, b.name.c_str(),
                     r.vertex.index, describe(position(r.vertex)).c_str(), b.uv1[2 * r.vertex.index],
                     b.uv1[2 * r.vertex.index + 1], grey(r.lookup), grey(r.vertex_bake));
    }
    if (tied)
        std::fprintf(stderr,
                     "lightmap_at_vertices: %zu probes match coincident vertices on several charts (the first is "
                     "used); their lookups differ by up to %.2f %% (%s:%d)\n",
                     tied, 100.0 * worst_tie, probes_path.c_str(), (*probes)[worst_tie_probe].location.line);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const bool skip_missing = argc == 5 && std::string(argv[4]) == "--skip-missing";
    if (argc != 4 && !skip_missing) {
        std::fprintf(stderr, "usage: lightmap_at_vertices BAKE_DIR PROBES_FILE OUT.csv [--skip-missing]\n");
        return 2;
    }
    try {
        return run(argv[1], argv[2], argv[3], skip_missing);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lightmap_at_vertices: error: %s\n", e.what());
        return 1;
    }
}
