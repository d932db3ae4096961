#pragma once
// Files are read, and replaced, only when they are regular files. A FIFO blocks open() or
// read() forever, a device such as /dev/zero never ends, a directory reads as nothing: each
// is refused by name before a byte is read, so a hostile scene cannot hang a bake, and an
// output path naming one is never replaced.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace radbake {

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using InputFile = std::unique_ptr<std::FILE, FileCloser>;

// Empty when `path` names a regular file (symbolic links followed); otherwise why not, as
// "no such file", "not a regular file (a FIFO)", "not a regular file (a directory)", ...
std::string whyNotRegularFile(const std::string& path);

// Empty when `path` names a regular file or nothing at all, so that writing there replaces
// no directory, FIFO, device or socket; otherwise why not ("not a regular file (a FIFO), and
// only a regular file is replaced").
std::string whyNotReplaceable(const std::string& path);

// A check of the file actually opened, by its path as the open descriptor knows it (symbolic
// links resolved when it was opened): empty to accept it, else why not.
using OpenedFileCheck = std::function<std::string(const std::filesystem::path& opened)>;

// `path` opened for binary reading when it is a regular file, checked again on the open
// descriptor (a file swapped in between is refused too); null with `why` set otherwise.
// Never blocks: a FIFO is never opened, or opened without waiting for a writer and refused.
// A file larger than `max_bytes` is refused too ("larger than N bytes"), and one `check`
// refuses.
InputFile openRegularFile(const std::string& path, std::string& why, size_t max_bytes = SIZE_MAX,
                          const OpenedFileCheck& check = {});

// The whole regular file; nullopt with `why` set when it is not one, cannot be read, or holds
// more than `max_bytes` (checked before reading and while reading, for a file that grows).
std::optional<std::string> readRegularFile(const std::string& path, std::string& why, size_t max_bytes = SIZE_MAX,
                                           const OpenedFileCheck& check = {});

// "larger than N bytes": the reason a capped read gives.
std::string largerThan(size_t max_bytes);

}  // namespace radbake
