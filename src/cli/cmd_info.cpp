// `radbake info SCENE`: what was read, as text or JSON.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "core/memory.h"
#include "io/import.h"
#include "scene/two_sided.h"

namespace radbake::cli {
namespace {

struct InfoArgs {
    std::string scene;
    bool json = false;
    ImportOptions import;
};

int printInfo(const InfoArgs& args, Diagnostics& diagnostics) {
    std::optional<Scene> scene = importScene(args.scene, args.import, diagnostics);
    if (!scene) return kExitInputError;

    settleClosedTwoSided(*scene);  // as the bake sees it: closed two-sided meshes dark inside are one-sided
    const SceneSummary s = summarize(*scene);
    if (args.json) {
        // Nine significant digits, as before: enough for a float, without its binary tail.
        const auto nine = [](double value) {
            char text[32];
            std::snprintf(text, sizeof text, "%.9g", value);
            return std::strtod(text, nullptr);
        };
        nlohmann::ordered_json info;
        info["name"] = scene->name;
        info["triangles"] = s.triangles;
        info["polygons"] = s.polygons;
        info["vertices"] = s.vertices;
        info["hard_edge_vertices"] = scene->crease_split.vertices;
        info["hard_edge_copies"] = scene->crease_split.added;
        info["meshes"] = scene->meshes.size();
        info["two_sided_meshes"] = s.two_sided_meshes;
        info["two_sided_polygons"] = s.two_sided_polygons;
        info["two_sided_closed_meshes"] = s.two_sided_closed_meshes;
        info["area"] = nine(s.area);
        info["bounds"]["min"] = {nine(s.bounds_min.x), nine(s.bounds_min.y), nine(s.bounds_min.z)};
        info["bounds"]["max"] = {nine(s.bounds_max.x), nine(s.bounds_max.y), nine(s.bounds_max.z)};
        info["materials"] = s.materials;
        info["emitters"] = s.emitters;
        info["lights"] = s.lights;
        info["cameras"] = scene->cameras.size();
        info["input_files"] = scene->input_files;
        if (!scene->refused_inputs.empty()) info["refused_inputs"] = scene->refused_inputs;
        info["warnings"] = diagnostics.warningCount();
        // One line; a file name in another encoding becomes U+FFFD, never an exception.
        std::printf("%s\n", info.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace).c_str());
    } else {
        std::printf("scene      %s\n", args.scene.c_str());
        std::printf("meshes     %zu\n", scene->meshes.size());
        // Lit on both sides: the bake gives each a back twin, with its own light and outputs.
        std::printf("two-sided  %zu meshes, %zu polygons\n", s.two_sided_meshes, s.two_sided_polygons);
        // Two-sided in the file, but closed with nothing lit inside: their backs are dark (0, exact).
        std::printf("           %zu closed, dark inside: one-sided\n", s.two_sided_closed_meshes);
        std::printf("polygons   %zu\n", s.polygons);
        std::printf("triangles  %zu\n", s.triangles);
        std::printf("vertices   %zu (%zu split at hard edges, %zu copies)\n", s.vertices,
                    scene->crease_split.vertices, scene->crease_split.added);
        std::printf("area       %.6g m^2\n", s.area);
        std::printf("bounds     [%.6g %.6g %.6g] .. [%.6g %.6g %.6g]\n", s.bounds_min.x, s.bounds_min.y,
                    s.bounds_min.z, s.bounds_max.x, s.bounds_max.y, s.bounds_max.z);
        std::printf("materials  %zu\n", s.materials);
        std::printf("emitters   %zu polygons\n", s.emitters);
        std::printf("lights     %zu\n", s.lights);
        std::printf("cameras    %zu\n", scene->cameras.size());
        if (!scene->refused_inputs.empty())
            std::printf("refused    %zu files (outside the read roots, or not regular files)\n",
                        scene->refused_inputs.size());
        std::printf("warnings   %d\n", diagnostics.warningCount());
    }
    return kExitOk;
}

// The command's boundary: an allocation failing anyway is a located error and exit 1, never an abort.
int runInfo(const InfoArgs& args) {
    Diagnostics diagnostics;
    printDiagnosticsToStderr(diagnostics);
    try {
        return printInfo(args, diagnostics);
    } catch (const std::bad_alloc&) {
        diagnostics.error({args.scene, 0, 0}, outOfMemoryMessage("summarising the scene"));
    } catch (const std::exception& e) {
        diagnostics.error({args.scene, 0, 0}, std::string("info failed: ") + e.what());
    }
    return kExitInputError;
}

}  // namespace

void addInfoCommand(CLI::App& app, int& result) {
    auto args = std::make_shared<InfoArgs>();
    CLI::App* cmd = app.add_subcommand("info", "Print what was read from a scene file");
    cmd->add_option("scene", args->scene, "Scene file (VRML97, VRML 1.0, or any format Assimp reads)")->required();
    cmd->add_flag("--json", args->json, "Print a JSON object on stdout");
    addSceneScaleOptions(*cmd, args->import);
    addReadRootOption(*cmd, args->import);
    addMaxMemoryOption(*cmd, args->import.max_memory_mb);
    cmd->add_flag("--strict", args->import.strict, "Unknown VRML nodes and fields are errors");
    cmd->callback([args, &result] { result = runInfo(*args); });
}

}  // namespace radbake::cli
