#include "pipeline/lightmap_scales.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>

#include "pipeline/side_file.h"
#include "scene/two_sided.h"

namespace radbake {

std::optional<std::vector<LightmapScaleRule>> parseLightmapScales(const std::string& text, const std::string& path,
                                                                  Diagnostics& diagnostics) {
    std::vector<LightmapScaleRule> rules;
    std::map<std::string, int> first_line;
    const int errors_before = diagnostics.errorCount();
    forEachSideFileLine(text, [&](int line, const std::string& content, const std::string& raw) {
        const size_t split = content.find_last_of(" \t");
        const SourceLocation where{path, line, 1};
        if (split == std::string::npos) {
            diagnostics.error(where, "expected 'NAME SCALE' (a mesh or material name, then its texel-density scale)");
            return;
        }
        LightmapScaleRule rule{trimSpaces(content.substr(0, split)), 0.0, where};
        const std::string number = content.substr(split + 1);
        char* end = nullptr;
        errno = 0;
        rule.scale = std::strtod(number.c_str(), &end);
        if (end != number.c_str() + number.size() || errno != 0 || !std::isfinite(rule.scale) || !(rule.scale > 0.0)) {
            diagnostics.error({path, line, static_cast<int>(raw.find(number)) + 1},
                              "lightmap scale '" + number + "' of '" + rule.name + "' is not a positive number");
            return;
        }
        if (const auto [it, added] = first_line.emplace(rule.name, line); !added) {
            diagnostics.error(where, "'" + rule.name + "' is given a lightmap scale twice (first on line " +
                                         std::to_string(it->second) + ")");
            return;
        }
        rules.push_back(std::move(rule));
    });
    if (diagnostics.errorCount() > errors_before) return std::nullopt;
    return rules;
}

std::optional<std::vector<LightmapScaleRule>> readLightmapScales(const std::string& path, Diagnostics& diagnostics) {
    const std::optional<std::string> text = readSideFile(path, "lightmap scale file", diagnostics);
    if (!text) return std::nullopt;
    return parseLightmapScales(*text, path, diagnostics);
}

std::vector<double> meshTexelScales(const Scene& scene, const std::vector<LightmapScaleRule>& rules,
                                    Diagnostics& diagnostics) {
    std::map<std::string, size_t> by_name;
    for (size_t r = 0; r < rules.size(); ++r) by_name.emplace(rules[r].name, r);
    std::vector<bool> used(rules.size(), false);
    std::vector<double> scales(scene.meshes.size(), 1.0);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        // A back twin takes its front's scale (its name is the front's plus " (back)").
        const Mesh& mesh = scene.meshes[frontMesh(scene, static_cast<uint32_t>(m))];
        auto it = by_name.find(mesh.name);
        if (it == by_name.end() && mesh.material < scene.materials.size())
            it = by_name.find(scene.materials[mesh.material].name);
        if (it == by_name.end()) continue;
        scales[m] = rules[it->second].scale;
        used[it->second] = true;
    }
    for (size_t r = 0; r < rules.size(); ++r)
        if (!used[r])
            diagnostics.warning(rules[r].location, "no mesh takes the lightmap scale of '" + rules[r].name +
                                                       "' (no mesh or material of the scene has that name)");
    return scales;
}

}  // namespace radbake
