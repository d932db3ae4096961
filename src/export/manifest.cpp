#include "export/manifest.h"

#include <algorithm>
#include <system_error>

#include "core/json.h"
#include "export/hash.h"
#include "export/output_transaction.h"

namespace radbake {

namespace fs = std::filesystem;

namespace {

// Both sides absolute and normalised, so "out/./manifest.json" is recognised as the manifest.
fs::path comparable(const fs::path& path) {
    std::error_code ec;
    const fs::path absolute = fs::absolute(path, ec);
    return (ec ? path : absolute).lexically_normal();
}

}  // namespace

bool writeManifest(const fs::path& manifest_path, const fs::path& root, std::vector<std::string> relative_files,
                   const std::string& generator, Diagnostics& diagnostics) {
    for (std::string& name : relative_files) name = fs::path(name).lexically_normal().generic_string();
    std::sort(relative_files.begin(), relative_files.end());
    relative_files.erase(std::unique(relative_files.begin(), relative_files.end()), relative_files.end());

    const fs::path manifest = comparable(manifest_path);
    std::string json = "{\n  \"generator\": " + jsonString(generator) + ",\n  \"files\": [";
    bool first = true;
    for (const std::string& name : relative_files) {
        const fs::path path = root / name;
        if (comparable(path) == manifest) continue;
        std::error_code ec;
        const uintmax_t bytes = fs::file_size(path, ec);
        if (ec) {
            diagnostics.error({path.string(), 0, 0}, "cannot list output in the manifest: " + ec.message());
            return false;
        }
        const std::optional<std::string> digest = sha256File(path, diagnostics);
        if (!digest) return false;
        json += std::string(first ? "" : ",") + "\n    {\"path\": " + jsonString(name) +
                ", \"bytes\": " + std::to_string(bytes) + ", \"sha256\": \"" + *digest + "\"}";
        first = false;
    }
    json += first ? "]\n}\n" : "\n  ]\n}\n";
    return writeFileBytes(manifest_path, json, diagnostics);
}

}  // namespace radbake
