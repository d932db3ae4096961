// Golden-file comparison: each kind of file is loaded (compare_load.h), turned into Samples
// (channels of one value per sample, plus a layout text and exact data that must match), then
// compared channel by channel.
#include "export/compare.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "export/compare_load.h"

namespace radbake {
namespace {

namespace fs = std::filesystem;

struct Samples {
    // One compared quantity, one value per sample. Light channels pass within rel_tol or
    // abs_tol; geometry channels only within their absolute tolerance (geometryTolerance).
    struct Channel {
        std::string name;
        std::vector<double> values;
        bool geometry = false;
        enum class Kind { Position, Normal, Uv } kind = Kind::Position;
    };
    std::vector<Channel> channels;
    size_t count = 0;
    std::string layout;                      // must be equal on both sides
    const char* unit = "vertex";             // "texel", "vertex", "probe"
    int width = 0;                           // images: texel (x, y) from the index
    std::vector<std::pair<size_t, std::string>> groups;  // (first sample, name), glb primitives
    // Data that must match exactly for the values to be comparable at all: a PLY vertex's
    // atlas index (the glb says it per primitive, in the layout).
    struct Exact {
        std::string name;
        std::vector<double> values;
    };
    std::vector<Exact> exact;
};

std::string kindOf(const fs::path& path) {
    const std::string ext = path.extension().string();
    if (ext == ".exr") return "exr";
    if (ext == ".glb") return "glb";
    if (ext == ".ply") return "ply";
    if (path.filename() == "probes.csv") return "probes";
    return "";
}

// Three light channels from interleaved RGB.
void addRgb(Samples& samples, const std::array<const char*, 3>& names, const std::vector<double>& rgb) {
    for (size_t c = 0; c < 3; ++c) {
        Samples::Channel channel;
        channel.name = names[c];
        channel.values.reserve(rgb.size() / 3);
        for (size_t i = c; i < rgb.size(); i += 3) channel.values.push_back(rgb[i]);
        samples.channels.push_back(std::move(channel));
    }
}

Samples fromImage(const RgbImage& image) {
    Samples samples;
    addRgb(samples, {"R", "G", "B"}, std::vector<double>(image.rgb.begin(), image.rgb.end()));
    samples.count = image.rgb.size() / 3;
    samples.layout = std::to_string(image.width) + "x" + std::to_string(image.height) + " image";
    samples.unit = "texel";
    samples.width = image.width;
    return samples;
}

Samples fromProbes(const ProbeFile& file) {
    Samples samples;
    addRgb(samples, {"r", "g", "b"}, file.rgb);
    samples.count = file.rgb.size() / 3;
    samples.unit = "probe";
    // Probes are the same probes only where their position and normal are written the same.
    samples.layout = file.header + "\n";
    for (const std::string& place : file.places) samples.layout += place + "\n";
    return samples;
}

// The geometry channels' names, and which of a block's arrays feeds each.
struct GeometrySet {
    std::vector<double> VertexBlock::*values;
    size_t components;
    std::array<const char*, 3> names;
    Samples::Channel::Kind kind;
    const char* glb_name;  // as the glb layout names it
    const char* ply_name;
};
const GeometrySet kGeometry[] = {
    {&VertexBlock::positions, 3, {"x", "y", "z"}, Samples::Channel::Kind::Position, "POSITION", "x y z"},
    {&VertexBlock::normals, 3, {"nx", "ny", "nz"}, Samples::Channel::Kind::Normal, "NORMAL", "nx ny nz"},
    {&VertexBlock::uv0, 2, {"u0", "v0"}, Samples::Channel::Kind::Uv, "TEXCOORD_0", "u0 v0"},
    {&VertexBlock::uv1, 2, {"u1", "v1"}, Samples::Channel::Kind::Uv, "TEXCOORD_1", "u1 v1"},
};

// Every block's light, then geometry, channel after channel. Which attributes a block has is
// part of the layout; a block without one that another block has (a glb mesh without charts
// beside meshes with lightmap UVs) fills that channel with NaN, which matches NaN.
Samples fromMeshFile(const MeshFile& file, bool glb) {
    Samples samples;
    if (glb) addRgb(samples, {"R", "G", "B"}, {});
    else addRgb(samples, {"red", "green", "blue"}, {});
    std::vector<size_t> first_channel(std::size(kGeometry), 0);  // 0: no block has the set
    for (size_t g = 0; g < std::size(kGeometry); ++g) {
        const bool anywhere = std::any_of(file.blocks.begin(), file.blocks.end(),
                                          [&](const VertexBlock& block) { return !(block.*kGeometry[g].values).empty(); });
        if (!anywhere) continue;
        first_channel[g] = samples.channels.size();
        for (size_t c = 0; c < kGeometry[g].components; ++c) {
            Samples::Channel channel;
            channel.name = kGeometry[g].names[c];
            channel.geometry = true;
            channel.kind = kGeometry[g].kind;
            samples.channels.push_back(std::move(channel));
        }
    }
    Samples::Exact atlas{"lightmap", {}};
    bool has_atlas = false;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const VertexBlock& block : file.blocks) {
        std::string layout = (glb ? block.name + ": " : "") + std::to_string(block.count) + " vertices";
        std::string attributes;
        for (size_t g = 0; g < std::size(kGeometry); ++g) {
            if ((block.*kGeometry[g].values).empty()) continue;
            attributes += std::string(attributes.empty() ? "" : " ") + (glb ? kGeometry[g].glb_name : kGeometry[g].ply_name);
        }
        if (block.has_atlas) attributes += std::string(attributes.empty() ? "" : " ") + "lightmap";
        if (!attributes.empty()) layout += ": " + attributes;
        if (!block.lightmap.empty()) layout += ", lightmap " + block.lightmap;
        samples.layout += layout + "\n";
        if (glb) samples.groups.emplace_back(samples.count, block.name);

        for (size_t i = 0; i < block.light.size(); ++i) samples.channels[i % 3].values.push_back(block.light[i]);
        for (size_t g = 0; g < std::size(kGeometry); ++g) {
            if (first_channel[g] == 0) continue;
            const std::vector<double>& values = block.*kGeometry[g].values;
            const size_t n = kGeometry[g].components;
            for (size_t c = 0; c < n; ++c) {
                std::vector<double>& out = samples.channels[first_channel[g] + c].values;
                if (values.empty()) out.insert(out.end(), block.count, nan);
                for (size_t v = 0; v < values.size() / n; ++v) out.push_back(values[v * n + c]);
            }
        }
        has_atlas = has_atlas || block.has_atlas;
        atlas.values.insert(atlas.values.end(), block.atlas.begin(), block.atlas.end());
        samples.count += block.count;
    }
    if (has_atlas) samples.exact.push_back(std::move(atlas));
    return samples;
}

std::optional<Samples> loadSamples(const fs::path& path, const std::string& kind, std::string& problem) {
    try {
        if (kind == "exr") return fromImage(loadExrFile(path));
        if (kind == "glb") return fromMeshFile(loadGlbFile(path), true);
        if (kind == "ply") return fromMeshFile(loadPlyFile(path), false);
        if (kind == "probes") return fromProbes(loadProbesFile(path));
        problem = "not a kind radbake compares";
    } catch (const std::exception& e) {
        problem = path.string() + ": " + e.what();
    }
    return std::nullopt;
}

// ---- comparison ----

std::string placeName(const Samples& samples, size_t index) {
    if (samples.width > 0)
        return "texel (" + std::to_string(index % samples.width) + ", " + std::to_string(index / samples.width) + ")";
    for (auto it = samples.groups.rbegin(); it != samples.groups.rend(); ++it)
        if (index >= it->first) return it->second + " vertex " + std::to_string(index - it->first);
    return std::string(samples.unit) + " " + std::to_string(index);
}

// How far beyond tolerance: the smaller of the two ratios; above 1 fails.
double excessOf(double abs_err, double rel_err, const CompareOptions& options) {
    if (abs_err == 0.0) return 0.0;
    const double inf = std::numeric_limits<double>::infinity();
    const double by_abs = options.abs_tol > 0.0 ? abs_err / options.abs_tol : inf;
    const double by_rel = options.rel_tol > 0.0 ? rel_err / options.rel_tol : inf;
    return std::min(by_abs, by_rel);
}

// The first line where two layout texts differ (both lines, without their line breaks).
std::pair<std::string, std::string> firstDifferentLines(const std::string& a, const std::string& b) {
    std::istringstream in_a(a), in_b(b);
    std::string line_a, line_b;
    while (true) {
        const bool got_a = static_cast<bool>(std::getline(in_a, line_a));
        const bool got_b = static_cast<bool>(std::getline(in_b, line_b));
        if (!got_a) line_a = "nothing";
        if (!got_b) line_b = "nothing";
        if (line_a != line_b || (!got_a && !got_b)) return {line_a, line_b};
    }
}

// Empty when the two runs of exact data are equal (NaN matches NaN); else where they differ.
std::string exactDifference(const Samples& a, const Samples::Exact& ea, const Samples::Exact& eb) {
    if (ea.name != eb.name || ea.values.size() != eb.values.size())
        return "different layouts (" + ea.name + " vs " + eb.name + ")";
    for (size_t i = 0; i < ea.values.size(); ++i) {
        const double va = ea.values[i], vb = eb.values[i];
        if (va == vb || (std::isnan(va) && std::isnan(vb))) continue;
        char text[160];
        std::snprintf(text, sizeof text, " differs at %s: %.9g vs %.9g (must match exactly)", placeName(a, i).c_str(), va, vb);
        return ea.name + text;
    }
    return {};
}

// The geometry tolerance of a channel: positions scale with the extent of A's positions
// (the diagonal of their bounding box), normals and UVs are in units of their own.
double geometryTolerance(const Samples::Channel& channel, double extent, const CompareOptions& options) {
    switch (channel.kind) {
        case Samples::Channel::Kind::Position: return options.position_tol * extent;
        case Samples::Channel::Kind::Normal: return options.normal_tol;
        case Samples::Channel::Kind::Uv: return options.uv_tol;
    }
    return 0.0;
}

double positionExtent(const Samples& samples) {
    double sum_sq = 0.0;
    for (const Samples::Channel& channel : samples.channels) {
        if (!channel.geometry || channel.kind != Samples::Channel::Kind::Position) continue;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (double v : channel.values) {
            if (!std::isfinite(v)) continue;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
        if (hi >= lo) sum_sq += (hi - lo) * (hi - lo);
    }
    return std::sqrt(sum_sq);
}

void compareSamples(const Samples& a, const Samples& b, const CompareOptions& options, FileDifference& out) {
    out.samples = a.count;
    if (a.layout != b.layout) {
        out.comparable = false;
        const auto [line_a, line_b] = firstDifferentLines(a.layout, b.layout);
        out.problem = "different layouts (" + line_a + " vs " + line_b + ")";
        return;
    }
    for (size_t e = 0; e < a.exact.size(); ++e) {
        const std::string problem = exactDifference(a, a.exact[e], b.exact[e]);
        if (!problem.empty()) {
            out.comparable = false;
            out.problem = problem;
            return;
        }
    }
    const double inf = std::numeric_limits<double>::infinity();
    const double extent = positionExtent(a);
    for (size_t c = 0; c < a.channels.size(); ++c) {
        const Samples::Channel& ca = a.channels[c];
        const Samples::Channel& cb = b.channels[c];
        const double geometry_tol = ca.geometry ? geometryTolerance(ca, extent, options) : 0.0;
        ChannelDifference channel;
        channel.name = ca.name;
        double sum_sq = 0.0;
        for (size_t i = 0; i < a.count; ++i) {
            const double va = ca.values[i], vb = cb.values[i];
            double abs_err = std::fabs(va - vb), rel_err = 0.0;
            if (std::isnan(va) && std::isnan(vb)) abs_err = 0.0;
            else if (std::isnan(abs_err)) abs_err = inf;  // NaN on one side, or inf - inf
            if (abs_err > 0.0) rel_err = abs_err / std::max(std::fabs(va), std::fabs(vb));
            if (std::isnan(rel_err)) rel_err = inf;
            sum_sq += abs_err * abs_err;
            channel.max_abs = std::max(channel.max_abs, abs_err);
            channel.max_rel = std::max(channel.max_rel, rel_err);
            double excess = excessOf(abs_err, rel_err, options);
            if (ca.geometry) excess = abs_err == 0.0 ? 0.0 : geometry_tol > 0.0 ? abs_err / geometry_tol : inf;
            if (excess > channel.worst_excess) {
                channel.worst_excess = excess;
                channel.worst = i;
                channel.worst_a = va;
                channel.worst_b = vb;
            }
        }
        channel.rmse = a.count ? std::sqrt(sum_sq / static_cast<double>(a.count)) : 0.0;
        channel.worst_place = placeName(a, channel.worst);
        if (channel.worst_excess > 1.0) out.within = false;
        out.channels.push_back(channel);
    }
}

FileDifference compareFiles(const fs::path& a, const fs::path& b, const std::string& label, const std::string& kind,
                            const CompareOptions& options) {
    FileDifference out;
    out.file = label;
    out.kind = kind;
    std::string problem;
    const std::optional<Samples> sa = loadSamples(a, kind, problem);
    const std::optional<Samples> sb = sa ? loadSamples(b, kind, problem) : std::nullopt;
    if (!sa || !sb) {
        out.comparable = false;
        out.problem = problem;
        return out;
    }
    compareSamples(*sa, *sb, options, out);
    return out;
}

// Relative paths of every comparable file under `root`, sorted; hidden entries (staging
// directories of a bake in progress) are skipped.
std::vector<std::string> comparableFiles(const fs::path& root) {
    std::vector<std::string> files;
    std::error_code error;
    for (auto it = fs::recursive_directory_iterator(root, error); !error && it != fs::recursive_directory_iterator();
         it.increment(error)) {
        if (it->path().filename().string().rfind('.', 0) == 0) {
            if (it->is_directory()) it.disable_recursion_pending();
            continue;
        }
        if (it->is_regular_file() && !kindOf(it->path()).empty())
            files.push_back(fs::relative(it->path(), root).generic_string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

int CompareResult::exitCode() const {
    if (!problems.empty()) return 2;
    for (const FileDifference& file : files)
        if (!file.comparable) return 2;
    for (const FileDifference& file : files)
        if (!file.within) return 1;
    return 0;
}

CompareResult comparePaths(const fs::path& a, const fs::path& b, const CompareOptions& options) {
    CompareResult result;
    try {
        std::error_code error;
        const bool a_dir = fs::is_directory(a, error), b_dir = fs::is_directory(b, error);
        if (a_dir && b_dir) {
            const std::vector<std::string> in_a = comparableFiles(a), in_b = comparableFiles(b);
            for (const std::string& file : in_b)
                if (!std::binary_search(in_a.begin(), in_a.end(), file)) result.problems.push_back(file + " is only in " + b.string());
            if (in_a.empty()) result.problems.push_back(a.string() + " holds no file radbake compares");
            for (const std::string& file : in_a) {
                if (!std::binary_search(in_b.begin(), in_b.end(), file)) {
                    result.problems.push_back(file + " is missing from " + b.string());
                    continue;
                }
                result.files.push_back(compareFiles(a / file, b / file, file, kindOf(file), options));
            }
        } else if (!a_dir && !b_dir && fs::is_regular_file(a, error) && fs::is_regular_file(b, error)) {
            const std::string kind = kindOf(a);
            if (kind.empty() || kind != kindOf(b))
                result.problems.push_back("cannot compare " + a.string() + " with " + b.string() +
                                          ": not two .exr, .glb, .ply or probes.csv files of the same kind");
            else
                result.files.push_back(compareFiles(a, b, a.filename().string(), kind, options));
        } else {
            for (const fs::path& p : {a, b})
                if (!fs::exists(p, error)) result.problems.push_back(p.string() + " does not exist");
            if (result.problems.empty()) result.problems.push_back("cannot compare a directory with a file");
        }
    } catch (const std::exception& e) {
        result.problems.push_back(std::string("compare failed: ") + e.what());
    }
    return result;
}

std::string formatCompareResult(const CompareResult& result) {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-32s %-6s %10s %12s %12s %12s  %s\n", "file", "chan", "samples", "rmse", "max_abs",
                  "max_rel", "worst");
    out += line;
    for (const FileDifference& file : result.files) {
        if (!file.comparable) {
            out += "NOT COMPARABLE " + file.file + ": " + file.problem + "\n";
            continue;
        }
        for (const ChannelDifference& c : file.channels) {
            std::snprintf(line, sizeof line, "%-32s %-6s %10zu %12.4g %12.4g %12.4g  %s\n", file.file.c_str(), c.name.c_str(),
                          file.samples, c.rmse, c.max_abs, c.max_rel, c.max_abs > 0.0 ? c.worst_place.c_str() : "-");
            out += line;
        }
    }
    for (const std::string& problem : result.problems) out += "NOT COMPARABLE: " + problem + "\n";
    for (const FileDifference& file : result.files) {
        if (!file.comparable || file.within) continue;
        const auto worst = std::max_element(file.channels.begin(), file.channels.end(),
                                            [](const auto& x, const auto& y) { return x.worst_excess < y.worst_excess; });
        std::snprintf(line, sizeof line, "DIFFERS %s: %s %s is %.9g vs %.9g (%.3g times the tolerance)\n", file.file.c_str(),
                      worst->worst_place.c_str(), worst->name.c_str(), worst->worst_a, worst->worst_b, worst->worst_excess);
        out += line;
    }
    const int code = result.exitCode();
    out += code == 0 ? "within tolerance\n" : code == 1 ? "differences beyond tolerance\n" : "not comparable\n";
    return out;
}

}  // namespace radbake
