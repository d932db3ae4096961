#include "export/manifest.h"

#include <algorithm>
#include <system_error>

#include "core/regular_file.h"
#include "export/hash.h"
#include "export/json_detail.h"
#include "export/output_transaction.h"
#include "export/stats_json.h"

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
                   const std::string& generator, const std::string& scene, Diagnostics& diagnostics) {
    for (std::string& name : relative_files) name = fs::path(name).lexically_normal().generic_string();
    std::sort(relative_files.begin(), relative_files.end());
    relative_files.erase(std::unique(relative_files.begin(), relative_files.end()), relative_files.end());

    const fs::path manifest = comparable(manifest_path);
    json_detail::Json files = json_detail::Json::array();
    for (const std::string& name : relative_files) {
        const fs::path path = root / name;
        if (comparable(path) == manifest || name == kTimingsJsonName) continue;
        std::error_code ec;
        const uintmax_t bytes = fs::file_size(path, ec);
        if (ec) {
            diagnostics.error({path.string(), 0, 0}, "cannot list output in the manifest: " + ec.message());
            return false;
        }
        const std::optional<std::string> digest = sha256File(path, diagnostics);
        if (!digest) return false;
        json_detail::Json entry;
        entry["path"] = name;
        entry["bytes"] = bytes;
        entry["sha256"] = *digest;
        files.push_back(std::move(entry));
    }
    json_detail::Json json;
    json["generator"] = generator;
    json["scene"] = scene;
    // Said in the file, so a reader checking the directory knows the one file not listed.
    json["excluded"] = {kTimingsJsonName};
    json["files"] = std::move(files);
    const std::string text = json_detail::dump(json, 2) + "\n";
    return writeFileBytes(manifest_path, text, diagnostics);
}

std::optional<ManifestContents> readManifest(const fs::path& path, std::string& why) {
    const std::optional<std::string> text = readRegularFile(path.string(), why);
    if (!text) return std::nullopt;
    try {
        const auto json = json_detail::Json::parse(*text);
        if (json.at("generator").get<std::string>().rfind("radbake", 0) != 0) {
            why = "not written by radbake";
            return std::nullopt;
        }
        ManifestContents contents;
        if (json.contains("scene")) contents.scene = json.at("scene").get<std::string>();
        for (const auto& entry : json.at("files")) contents.files.push_back(entry.at("path").get<std::string>());
        contents.files.push_back(kTimingsJsonName);
        contents.files.push_back(path.filename().string());
        for (const std::string& name : contents.files) {
            if (!isSafeOutputName(name)) {
                why = "it lists '" + name + "', a path outside the folder";
                return std::nullopt;
            }
        }
        return contents;
    } catch (const std::exception& e) {
        why = std::string("not a radbake manifest (") + e.what() + ")";
        return std::nullopt;
    }
}

}  // namespace radbake
