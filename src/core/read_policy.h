#pragma once
// What a scene may read: regular files under its read roots (the scene file's folder, and any
// folder given with --read-root), each no larger than a cap. A scene made by someone else
// names paths of its own choosing (an Inline of /etc/shadow, a glTF buffer of ../../secret):
// every file a reader opens on a scene's behalf is checked here first, after resolving it
// (symbolic links included), so the scene cannot reach out of its tree.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "core/regular_file.h"

namespace radbake {

// The largest file a scene may make us read, and the largest text a gzip stream may inflate
// to: far above real scenes, far below what exhausts a machine.
inline constexpr size_t kDefaultMaxInputBytes = size_t(1) << 30;

struct ReadPolicy {
    std::vector<std::filesystem::path> roots;  // canonical; no roots: every path is refused
    std::filesystem::path scene_file;          // canonical; read wherever it leads
    size_t max_bytes = kDefaultMaxInputBytes;

    // Empty when `path` resolves to a place under one of the roots (whether or not a file is
    // there); otherwise why not, naming the path and where it resolves to.
    std::string whyOutside(const std::string& path) const;
    // whyOutside, then, when something is there, whyNotRegularFile: empty when a scene may
    // read `path` or when nothing is there (the caller's "missing", named in the depfile).
    std::string whyRefused(const std::string& path) const;
    // The check openRegularFile makes on the file it opened: under a root, or the scene file.
    // A path swapped for a symbolic link between whyOutside and the open is refused so.
    OpenedFileCheck openedCheck() const;
};

// The policy of the scene file at `scene_path`: its own folder, then each of `extra_roots`
// (a root that does not exist is kept by its absolute path, and holds nothing).
// policy->openedCheck(), or no check without a policy.
inline OpenedFileCheck openedCheckOf(const ReadPolicy* policy) { return policy ? policy->openedCheck() : OpenedFileCheck{}; }

ReadPolicy readPolicyFor(const std::string& scene_path, const std::vector<std::string>& extra_roots,
                         size_t max_bytes = kDefaultMaxInputBytes);

}  // namespace radbake
