#include "core/regular_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace radbake {
namespace {

std::string notRegular(mode_t mode) {
    const char* kind = S_ISDIR(mode)    ? "a directory"
                       : S_ISFIFO(mode) ? "a FIFO"
                       : S_ISCHR(mode)  ? "a character device"
                       : S_ISBLK(mode)  ? "a block device"
                       : S_ISSOCK(mode) ? "a socket"
                                        : "of an unknown kind";
    return std::string("not a regular file (") + kind + ")";
}

std::string errnoReason(int error) { return error == ENOENT ? "no such file" : std::strerror(error); }

// Where the open descriptor `fd` leads, as the kernel resolved it when opening; empty when
// /proc is not mounted (the check then sees an empty path and refuses).
std::filesystem::path openedPath(int fd) {
    std::error_code ec;
    std::filesystem::path target = std::filesystem::read_symlink("/proc/self/fd/" + std::to_string(fd), ec);
    return ec ? std::filesystem::path() : target;
}

}  // namespace

std::string whyNotRegularFile(const std::string& path) {
    struct stat status {};
    if (::stat(path.c_str(), &status) != 0) return errnoReason(errno);
    return S_ISREG(status.st_mode) ? std::string() : notRegular(status.st_mode);
}

std::string whyNotReplaceable(const std::string& path) {
    struct stat status {};
    if (::stat(path.c_str(), &status) != 0) return errno == ENOENT ? std::string() : std::strerror(errno);
    return S_ISREG(status.st_mode) ? std::string() : notRegular(status.st_mode) + ", and only a regular file is replaced";
}

std::string largerThan(size_t max_bytes) { return "larger than " + std::to_string(max_bytes) + " bytes"; }

InputFile openRegularFile(const std::string& path, std::string& why, size_t max_bytes, const OpenedFileCheck& check) {
    // Checked before opening too: opening a device can itself act (a tape rewinds).
    why = whyNotRegularFile(path);
    if (!why.empty()) return nullptr;
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        why = errnoReason(errno);
        return nullptr;
    }
    struct stat status {};
    if (::fstat(fd, &status) != 0) why = errnoReason(errno);
    else if (!S_ISREG(status.st_mode)) why = notRegular(status.st_mode);
    else if (static_cast<uint64_t>(status.st_size) > max_bytes) why = largerThan(max_bytes);
    else if (check) why = check(openedPath(fd));
    if (!why.empty()) {
        ::close(fd);
        return nullptr;
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);  // plain reads from here on
    std::FILE* file = ::fdopen(fd, "rb");
    if (!file) {
        why = errnoReason(errno);
        ::close(fd);
    }
    return InputFile(file);
}

std::optional<std::string> readRegularFile(const std::string& path, std::string& why, size_t max_bytes,
                                           const OpenedFileCheck& check) {
    const InputFile file = openRegularFile(path, why, max_bytes, check);
    if (!file) return std::nullopt;
    std::string bytes;
    char block[1 << 16];
    size_t got = 0;
    while ((got = std::fread(block, 1, sizeof block, file.get())) > 0) {
        if (got > max_bytes - bytes.size()) {
            why = largerThan(max_bytes);
            return std::nullopt;
        }
        bytes.append(block, got);
    }
    if (std::ferror(file.get())) {
        why = errnoReason(errno);
        return std::nullopt;
    }
    return bytes;
}

}  // namespace radbake
