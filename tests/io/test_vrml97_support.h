#pragma once
// Helpers for the VRML97 reader tests: literal files written to a fresh temporary folder.
#include <filesystem>
#include <fstream>
#include <string>

#include "io/vrml/vrml_reader.h"

namespace vrml_test {

inline std::filesystem::path tempDir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("radbake_vrml97_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::string writeFile(const std::filesystem::path& path, const std::string& bytes) {
    std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path.string();
}

struct Read {
    radbake::Scene scene;
    radbake::Diagnostics diagnostics;
    bool ok = false;

    // Messages formatted "file:line:col: severity: message", joined by newlines.
    std::string messages() const {
        std::string all;
        for (const auto& d : diagnostics.all()) all += radbake::formatDiagnostic(d) + "\n";
        return all;
    }
    bool has(const std::string& fragment) const { return messages().find(fragment) != std::string::npos; }
    double area() const {
        double sum = 0.0;
        for (const auto& mesh : scene.meshes)
            for (size_t t = 0; t < mesh.triangles.size(); ++t) sum += radbake::triangleArea(mesh, t);
        return sum;
    }
    size_t triangles() const {
        size_t n = 0;
        for (const auto& mesh : scene.meshes) n += mesh.triangles.size();
        return n;
    }
};

inline Read readPath(const std::string& path, bool strict = false) {
    Read r;
    r.ok = radbake::readVrml(path, radbake::VrmlOptions{strict}, r.scene, r.diagnostics);
    return r;
}

// Writes `body` after a VRML97 header into its own temp folder and reads it.
inline Read readVrml97(const std::string& name, const std::string& body, bool strict = false) {
    const std::string path = writeFile(tempDir(name) / "scene.wrl", "#VRML V2.0 utf8\n" + body);
    return readPath(path, strict);
}

}  // namespace vrml_test
