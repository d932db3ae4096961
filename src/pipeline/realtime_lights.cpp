#include "pipeline/realtime_lights.h"

#include <algorithm>
#include <map>

#include "pipeline/side_file.h"

namespace radbake {
namespace {

bool meshEmits(const Scene& scene, const Mesh& mesh) {
    if (!mesh.polygon_emission.empty())
        return std::any_of(mesh.polygon_emission.begin(), mesh.polygon_emission.end(),
                           [](const Vec3& e) { return e != Vec3(0.0f); });
    return mesh.material < scene.materials.size() && scene.materials[mesh.material].emission != Vec3(0.0f);
}

}  // namespace

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
        bool found = false, dark_mesh = false;
        for (Light& light : scene.lights)
            if (light.name == entry.name) found = light.realtime = true;
        for (Mesh& mesh : scene.meshes) {
            if (mesh.name != entry.name) continue;
            if (meshEmits(scene, mesh)) {
                mesh.realtime_light = entry.name;
                found = true;
            } else {
                dark_mesh = true;
            }
        }
        if (found) continue;
        ok = false;
        if (dark_mesh) {
            diagnostics.error(entry.location, "'" + entry.name + "' is a mesh that emits no light: only lights and "
                                                                 "emissive meshes can be real-time lights");
            continue;
        }
        std::string known;
        for (const Light& light : scene.lights)
            if (!light.name.empty()) known += (known.empty() ? "" : ", ") + ("'" + light.name + "'");
        for (const Mesh& mesh : scene.meshes)
            if (!mesh.name.empty() && meshEmits(scene, mesh) && known.find("'" + mesh.name + "'") == std::string::npos)
                known += (known.empty() ? "" : ", ") + ("'" + mesh.name + "'");
        diagnostics.error(entry.location, "no light or emissive mesh is named '" + entry.name + "'" +
                                              (known.empty() ? " (the scene has no named light)" : " (named lights: " + known + ")"));
    }
    return ok;
}

}  // namespace radbake
