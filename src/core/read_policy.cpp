#include "core/read_policy.h"

#include <algorithm>

#include "core/regular_file.h"

namespace radbake {
namespace {

namespace fs = std::filesystem;

// The path with every symbolic link of the part that exists resolved, and `.` and `..`
// folded: where opening it would land.
fs::path resolved(const std::string& path) {
    std::error_code ec;
    fs::path absolute = fs::absolute(path, ec);
    if (ec) return fs::path(path).lexically_normal();
    fs::path out = fs::weakly_canonical(absolute, ec);
    return ec ? absolute.lexically_normal() : out;
}

bool isUnder(const fs::path& path, const fs::path& root) {
    auto p = path.begin();
    for (auto r = root.begin(); r != root.end(); ++r, ++p) {
        if (r->empty()) continue;  // the empty name after a trailing separator
        if (p == path.end() || *p != *r) return false;
    }
    return true;
}

}  // namespace

std::string ReadPolicy::whyOutside(const std::string& path) const {
    const fs::path target = resolved(path);
    if (std::any_of(roots.begin(), roots.end(), [&](const fs::path& root) { return isUnder(target, root); }))
        return {};
    std::string why = target.string() == path ? std::string("outside") : "resolved to '" + target.string() + "', outside";
    why += roots.size() == 1 ? " the read root '" + roots.front().string() + "'" : " every read root";
    return why + "; --read-root DIR allows reading under DIR";
}

std::string ReadPolicy::whyRefused(const std::string& path) const {
    if (std::string why = whyOutside(path); !why.empty()) return why;
    std::error_code ec;
    if (!fs::exists(path, ec)) return {};
    return whyNotRegularFile(path);
}

OpenedFileCheck ReadPolicy::openedCheck() const {
    return [this](const fs::path& opened) -> std::string {
        if (!opened.empty() && (opened == scene_file || std::any_of(roots.begin(), roots.end(), [&](const fs::path& root) {
                                    return isUnder(opened, root);
                                })))
            return {};
        return "opened '" + opened.string() + "', outside the read roots (the path changed after it was checked)";
    };
}

ReadPolicy readPolicyFor(const std::string& scene_path, const std::vector<std::string>& extra_roots, size_t max_bytes) {
    ReadPolicy policy;
    policy.max_bytes = max_bytes;
    // The folder the scene's relative names start from: the one its path names, even when
    // the scene file itself is a symbolic link to elsewhere.
    std::error_code ec;
    policy.scene_file = resolved(scene_path);
    std::vector<std::string> roots{fs::absolute(scene_path, ec).parent_path().string()};
    roots.insert(roots.end(), extra_roots.begin(), extra_roots.end());
    for (const std::string& root : roots) {
        const fs::path canonical = resolved(root);
        if (std::find(policy.roots.begin(), policy.roots.end(), canonical) == policy.roots.end())
            policy.roots.push_back(canonical);
    }
    return policy;
}

}  // namespace radbake
