#include "pipeline/realtime_lights.h"

#include <map>

#include "pipeline/side_file.h"

namespace radbake {

std::optional<std::vector<RealtimeLightName>> parseRealtimeLights(const std::string& text, const std::string& path,
                                                                  Diagnostics& diagnostics) {
    std::vector<RealtimeLightName> names;
    std::map<std::string, int> first_line;
    const int errors_before = diagnostics.errorCount();
    forEachSideFileLine(text, [&](int line, const std::string& name, const std::string&) {
        const SourceLocation where{path, line, 1};
        if (const auto [it, added] = first_line.emplace(name, line); !added) {
            diagnostics.error(where, "'" + name + "' is named twice (first on line " + std::to_string(it->second) + ")");
            return;
        }
        names.push_back({name, where});
    });
    if (diagnostics.errorCount() > errors_before) return std::nullopt;
    return names;
}

std::optional<std::vector<RealtimeLightName>> readRealtimeLights(const std::string& path, Diagnostics& diagnostics) {
    const std::optional<std::string> text = readSideFile(path, "real-time light file", diagnostics);
    if (!text) return std::nullopt;
    return parseRealtimeLights(*text, path, diagnostics);
}

bool markRealtimeLights(Scene& scene, const std::vector<RealtimeLightName>& names, Diagnostics& diagnostics) {
    bool ok = true;
    for (const RealtimeLightName& entry : names) {
        bool found = false;
        for (Light& light : scene.lights)
            if (light.name == entry.name) found = light.realtime = true;
        if (found) continue;
        ok = false;
        bool emissive_mesh = false;
        for (const Mesh& mesh : scene.meshes)
            emissive_mesh |= mesh.name == entry.name && scene.materials[mesh.material].emission != Vec3(0.0f);
        if (emissive_mesh) {
            diagnostics.error(entry.location, "'" + entry.name +
                                                  "' is an emissive mesh: only punctual lights (point, spot, "
                                                  "directional, the sun) can be real-time lights so far");
            continue;
        }
        std::string known;
        for (const Light& light : scene.lights)
            if (!light.name.empty()) known += (known.empty() ? "" : ", ") + ("'" + light.name + "'");
        diagnostics.error(entry.location, "no light is named '" + entry.name + "'" +
                                              (known.empty() ? " (the scene has no named light)" : " (named lights: " + known + ")"));
    }
    return ok;
}

}  // namespace radbake
