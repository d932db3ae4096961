#include "export/output_transaction.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include "core/regular_file.h"

namespace radbake {

namespace fs = std::filesystem;

namespace {

// "baked/x/" and "baked/x/." both name the directory x; the staging directory goes beside it.
fs::path normalisedDir(const fs::path& dir) {
    std::error_code ec;
    fs::path p = fs::absolute(dir, ec);
    if (ec) p = dir;
    p = p.lexically_normal();
    if (p.has_parent_path() && p.filename().empty()) p = p.parent_path();
    return p;
}

SourceLocation at(const fs::path& p) { return {p.string(), 0, 0}; }

// The process's umask, read without changing it (umask(2) can only be read by setting it,
// which would race with a host program's other threads); Linux reports it in /proc.
mode_t currentUmask() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(std::strtoul(line.c_str() + 6, nullptr, 8));
    const mode_t mask = ::umask(022);
    ::umask(mask);
    return mask;
}

// Same bytes: a file whose content did not change keeps its old inode and time (Ninja's restat).
bool sameBytes(const fs::path& a, const fs::path& b) {
    std::error_code ec;
    if (fs::file_size(a, ec) != fs::file_size(b, ec) || ec) return false;
    std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
    char ba[1 << 16], bb[1 << 16];
    while (fa && fb) {
        fa.read(ba, sizeof ba);
        fb.read(bb, sizeof bb);
        if (fa.gcount() != fb.gcount() || std::memcmp(ba, bb, static_cast<size_t>(fa.gcount())) != 0) return false;
    }
    return fa.eof() && fb.eof();
}

// Staging directories a killed bake left (".radbake-tmp-*" inside OUTDIR, ".<name>.radbake-tmp-*"
// beside it): those whose lock (held by every live bake on its own staging directory) is free.
void removeStaleStaging(const fs::path& out_dir) {
    std::error_code ec;
    const std::string inside = ".radbake-tmp-", beside = "." + out_dir.filename().string() + ".radbake-tmp-";
    for (const auto& [dir, prefix] : {std::pair{out_dir, inside}, std::pair{out_dir.parent_path(), beside}}) {
        if (!fs::is_directory(dir, ec)) continue;
        std::vector<fs::path> stale;
        for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec))
            if (entry.is_directory(ec) && entry.path().filename().string().rfind(prefix, 0) == 0)
                stale.push_back(entry.path());
        for (const fs::path& path : stale) {
            // A live bake holds a lock on its own staging directory: only a dead one's opens.
            const int fd = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
            if (fd < 0) continue;
            if (::flock(fd, LOCK_EX | LOCK_NB) == 0) fs::remove_all(path, ec);
            ::close(fd);
        }
    }
}

// What the signal handler removes, kept in plain static storage: a handler may only call
// async-signal-safe functions (unlink, rmdir), so the paths are laid out in advance.
// Slot 0 is the staging directory; the others are files that may exist inside it.
// 256 slots: two per staged file (it and its backup) plus its directories, enough for a
// bake with a hundred lightmap atlases.
constexpr int kMaxSignalPaths = 256;
constexpr size_t kMaxPathBytes = 4096;
char g_signal_paths[kMaxSignalPaths][kMaxPathBytes];
std::atomic<int> g_signal_path_count{0};
// Set by cleanUpStagingOnSignals (a program's choice, never the library's): until then no
// transaction touches this process-wide table, so transactions on several threads of a host
// program share no state.
std::atomic<bool> g_signal_cleanup{false};

void forgetSignalPaths() {
    if (g_signal_cleanup.load()) g_signal_path_count.store(0);
}

void registerSignalPath(const fs::path& path) {
    if (!g_signal_cleanup.load()) return;
    const int slot = g_signal_path_count.load();
    const std::string text = path.string();
    if (slot >= kMaxSignalPaths || text.size() >= kMaxPathBytes) return;
    std::memcpy(g_signal_paths[slot], text.c_str(), text.size() + 1);
    g_signal_path_count.store(slot + 1);  // published only once the text is in place
}

void removeStagingOnSignal(int signal_number) {
    const int count = g_signal_path_count.load();
    // Directories were registered before their files, so reverse order empties them first.
    for (int i = count - 1; i >= 1; --i)
        if (unlink(g_signal_paths[i]) != 0) rmdir(g_signal_paths[i]);
    if (count > 0) rmdir(g_signal_paths[0]);
    ::signal(signal_number, SIG_DFL);
    ::raise(signal_number);
}

}  // namespace

void cleanUpStagingOnSignals() {
    g_signal_cleanup.store(true);
    for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) ::signal(signal_number, removeStagingOnSignal);
}

OutputTransaction::OutputTransaction(fs::path out_dir) : out_dir_(normalisedDir(out_dir)) {}

OutputTransaction::~OutputTransaction() {
    if (!committed_) abandon();
    unlock();
}

void OutputTransaction::unlock() {
    for (int* fd : {&lock_fd_, &staging_lock_fd_}) {
        if (*fd >= 0) ::close(*fd);  // closing releases the flock
        *fd = -1;
    }
}

bool OutputTransaction::lock(Diagnostics& diagnostics) {
    // An existing OUTDIR is locked itself (flock on the directory: no lock file to leave
    // behind; the kernel releases it when a bake dies, even by SIGKILL). A new OUTDIR needs no
    // lock: it appears by renaming a whole staging directory, and of two bakes racing to make
    // it the second rename fails, leaving the first bake's folder whole.
    std::error_code ec;
    if (!fs::is_directory(out_dir_, ec)) return true;
    lock_fd_ = ::open(out_dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (lock_fd_ < 0) {
        diagnostics.error(at(out_dir_), std::string("cannot open the output directory: ") + std::strerror(errno));
        return false;
    }
    if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
        const int saved = errno;
        unlock();
        diagnostics.error(at(out_dir_), saved == EWOULDBLOCK
                                            ? std::string("another bake is writing into this directory; nothing "
                                                          "written (bake into another directory, or after it)")
                                            : std::string("cannot lock the output directory: ") + std::strerror(saved));
        return false;
    }
    return true;
}

bool OutputTransaction::begin(Diagnostics& diagnostics) {
    std::error_code ec;
    if (fs::exists(out_dir_, ec) && !fs::is_directory(out_dir_, ec)) {
        diagnostics.error(at(out_dir_), "output path exists and is not a directory");
        return false;
    }
    const fs::path parent = out_dir_.parent_path();
    if (out_dir_.filename().empty() || parent.empty()) {
        diagnostics.error(at(out_dir_), "cannot use this directory for output");
        return false;
    }
    // Remember which parents are new, so that a failed bake leaves no empty directories behind.
    std::vector<fs::path> missing;
    for (fs::path p = parent; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    fs::create_directories(parent, ec);
    if (ec) {
        diagnostics.error(at(parent), "cannot create output directory: " + ec.message());
        return false;
    }
    created_dirs_.assign(missing.rbegin(), missing.rend());
    if (!lock(diagnostics)) {
        abandon();
        return false;
    }
    removeStaleStaging(out_dir_);

    // Inside an existing OUTDIR (same file system, nothing written outside it); beside a new
    // one, so that the whole directory can appear in one rename.
    const bool exists = fs::is_directory(out_dir_, ec);
    const fs::path staging_parent = exists ? out_dir_ : parent;
    std::string pattern =
        (staging_parent / ((exists ? std::string() : "." + out_dir_.filename().string()) + ".radbake-tmp-XXXXXX"))
            .string();
    if (!mkdtemp(pattern.data())) {
        diagnostics.error(at(staging_parent), std::string("cannot create a staging directory: ") + std::strerror(errno));
        abandon();
        return false;
    }
    staging_dir_ = pattern;
    // mkdtemp makes it 0700; a new OUTDIR is this directory renamed, and must have the mode
    // any directory the user makes would have.
    ::chmod(staging_dir_.c_str(), 0777 & ~currentUmask());
    staging_lock_fd_ = ::open(staging_dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (staging_lock_fd_ >= 0) ::flock(staging_lock_fd_, LOCK_EX);  // ours alone: never waits
    forgetSignalPaths();
    registerSignalPath(staging_dir_);
    return true;
}

namespace {

// A relative name with '/' separators that cannot leave the directory it is relative to.
bool isSafeRelativeName(std::string_view name) {
    if (name.empty() || name.front() == '/') return false;
    size_t start = 0;
    while (start <= name.size()) {
        const size_t end = std::min(name.find('/', start), name.size());
        const std::string_view part = name.substr(start, end - start);
        if (part.empty() || part == "." || part == "..") return false;
        start = end + 1;
    }
    return true;
}

// Backups live flat in the staging directory: "lightmaps/a_0.exr" -> ".old-lightmaps%2Fa_0.exr"
// ('%' is escaped first, so two names never share a backup).
std::string flatName(const std::string& name) {
    std::string out;
    for (char c : name) {
        if (c == '%') out += "%25";
        else if (c == '/') out += "%2F";
        else out += c;
    }
    return out;
}

}  // namespace

fs::path OutputTransaction::backupOf(const std::string& name) const { return staging_dir_ / (".old-" + flatName(name)); }

fs::path OutputTransaction::stage(std::string_view file_name) {
    const std::string name(file_name);
    if (!isSafeRelativeName(name)) {
        // The writer still gets somewhere harmless to write; commit() refuses the whole bake.
        rejected_.push_back(name);
        const fs::path scratch = staging_dir_ / (".rejected-" + std::to_string(rejected_.size()));
        registerSignalPath(scratch);
        return scratch;
    }
    const fs::path path = staging_dir_ / fs::path(name);
    if (std::find(staged_.begin(), staged_.end(), name) != staged_.end()) return path;
    staged_.push_back(name);
    if (!staging_dir_.empty()) {
        // Each directory is registered before the files in it: the signal handler removes
        // paths in reverse order, so a directory is empty by the time it reaches it.
        fs::path dir = staging_dir_;
        const fs::path relative_parent = fs::path(name).parent_path();
        for (const fs::path& part : relative_parent) {
            dir /= part;
            std::error_code ec;
            if (fs::create_directory(dir, ec)) registerSignalPath(dir);
            // On failure (a file of that name) the writer's open fails and reports the path.
        }
    }
    registerSignalPath(path);
    registerSignalPath(backupOf(name));
    return path;
}

void OutputTransaction::retire(std::string_view file_name) {
    const std::string name(file_name);
    if (!isSafeRelativeName(name)) {
        rejected_.push_back(name);
        return;
    }
    retired_.push_back(name);
    registerSignalPath(backupOf(name));
}

void OutputTransaction::retireUnstagedIn(std::string_view directory) {
    const std::string name(directory);
    if (!isSafeRelativeName(name)) {
        rejected_.push_back(name);
        return;
    }
    retired_dirs_.push_back(name);
}

bool OutputTransaction::checkNames(Diagnostics& diagnostics) const {
    for (const std::string& name : rejected_)
        diagnostics.error(at(out_dir_), "internal: output name '" + name +
                                            "' is not a relative path inside the output directory");
    return rejected_.empty();
}

std::vector<std::string> OutputTransaction::unstagedIn(const std::string& directory) const {
    std::vector<std::string> out;
    std::error_code ec;
    for (fs::directory_iterator it(out_dir_ / directory, ec), end; !ec && it != end; it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;  // sub-directories are not ours to judge
        const std::string name = directory + "/" + it->path().filename().string();
        if (std::find(staged_.begin(), staged_.end(), name) == staged_.end()) out.push_back(name);
    }
    std::sort(out.begin(), out.end());
    return out;
}

bool OutputTransaction::commit(Diagnostics& diagnostics) {
    if (staging_dir_.empty()) {
        diagnostics.error(at(out_dir_), "internal: output transaction committed before it began");
        return false;
    }
    if (!checkNames(diagnostics)) return false;
    std::error_code ec;
    for (const std::string& name : staged_) {
        if (!fs::is_regular_file(staging_dir_ / name, ec)) {
            diagnostics.error(at(staging_dir_ / name), "internal: staged output was never written");
            return false;
        }
    }
    if (!fs::exists(out_dir_, ec)) {
        // A new OUTDIR appears in one atomic step, complete.
        changed_ = staged_.size();
        fs::rename(staging_dir_, out_dir_, ec);
        if (ec) {
            diagnostics.error(at(out_dir_), "cannot move outputs into place: " + ec.message());
            return false;
        }
        forgetSignalPaths();
        committed_ = true;
        staging_dir_.clear();
        unlock();
        return true;
    }
    // OUTDIR appeared since begin() (another bake made it): lock it before changing it.
    if (lock_fd_ < 0 && !lock(diagnostics)) return false;
    if (!commitIntoExisting(diagnostics)) return false;
    forgetSignalPaths();
    committed_ = true;
    fs::remove_all(staging_dir_, ec);  // only backups of the replaced files remain there
    staging_dir_.clear();
    for (const std::string& dir : retired_dirs_) {
        const fs::path path = out_dir_ / dir;
        if (fs::is_directory(path, ec) && fs::is_empty(path, ec)) fs::remove(path, ec);
    }
    unlock();
    return true;
}

bool OutputTransaction::commitIntoExisting(Diagnostics& diagnostics) {
    // Each older file is first moved aside into the staging directory, so that a failure
    // half-way can put every one of them back.
    struct Step {
        std::string name;
        bool had_old = false;
        bool retired = false;  // no new file: the old one is only moved aside
    };
    changed_ = 0;
    std::vector<Step> done;
    std::vector<fs::path> made_dirs;  // directories of OUTDIR this commit created, in order
    std::error_code ec;
    auto rollBack = [&] {
        std::error_code ignored;
        for (auto it = done.rbegin(); it != done.rend(); ++it) {
            const fs::path target = out_dir_ / it->name;
            if (it->retired || fs::exists(staging_dir_ / it->name, ignored)) {
                // The new file never arrived; only the old one may need restoring.
            } else {
                fs::rename(target, staging_dir_ / it->name, ignored);
            }
            if (it->had_old) fs::rename(backupOf(it->name), target, ignored);
        }
        for (auto it = made_dirs.rbegin(); it != made_dirs.rend(); ++it) fs::remove(*it, ignored);
    };
    std::vector<std::string> retired = retired_;
    for (const std::string& dir : retired_dirs_) {
        for (std::string& name : unstagedIn(dir)) {
            registerSignalPath(backupOf(name));
            retired.push_back(std::move(name));
        }
    }
    for (const std::string& name : retired) {
        const fs::path target = out_dir_ / name;
        if (!fs::is_regular_file(target, ec)) continue;
        fs::rename(target, backupOf(name), ec);
        if (ec) {
            diagnostics.error(at(target), "cannot remove older output: " + ec.message());
            rollBack();
            return false;
        }
        done.push_back({name, true, true});
    }
    for (const std::string& name : staged_) {
        const fs::path target = out_dir_ / name;
        // Sub-directories ("lightmaps/") are made on the way, remembered for the roll-back.
        for (fs::path dir = out_dir_; const fs::path& part : fs::path(name).parent_path()) {
            dir /= part;
            if (fs::is_directory(dir, ec)) continue;
            if (!fs::create_directory(dir, ec)) {
                std::error_code ignored;
                diagnostics.error(at(dir), "cannot create output directory: " +
                                               (fs::exists(dir, ignored) ? std::string("a file is in the way")
                                                                         : ec.message()));
                rollBack();
                return false;
            }
            made_dirs.push_back(dir);
        }
        Step step{name, fs::exists(target, ec)};
        if (step.had_old && sameBytes(staging_dir_ / name, target)) continue;  // unchanged: keep the old file
        ++changed_;
        if (step.had_old) {
            fs::rename(target, backupOf(name), ec);
            if (ec) {
                diagnostics.error(at(target), "cannot replace older output: " + ec.message());
                rollBack();
                return false;
            }
        }
        done.push_back(step);
        fs::rename(staging_dir_ / name, target, ec);
        if (ec) {
            diagnostics.error(at(target), "cannot move output into place: " + ec.message());
            rollBack();
            return false;
        }
    }
    return true;
}

void OutputTransaction::abandon() {
    if (!staging_dir_.empty()) forgetSignalPaths();
    std::error_code ec;
    if (!staging_dir_.empty()) fs::remove_all(staging_dir_, ec);
    staging_dir_.clear();
    // Deepest first; fs::remove leaves a directory someone else has put files into.
    for (auto it = created_dirs_.rbegin(); it != created_dirs_.rend(); ++it) fs::remove(*it, ec);
    created_dirs_.clear();
    unlock();
}

namespace {

// Every byte to `fd`, through partial writes and signals; false with errno set otherwise.
bool writeAll(int fd, std::string_view bytes) {
    while (!bytes.empty()) {
        const ssize_t wrote = ::write(fd, bytes.data(), bytes.size());
        if (wrote < 0 && errno == EINTR) continue;
        if (wrote <= 0) return false;
        bytes.remove_prefix(static_cast<size_t>(wrote));
    }
    return true;
}

// Writes the temporary; empty on success, else why. What is already at `temporary` (a
// killed run's leftover) is replaced, unless it is a FIFO, a device or a link: O_NOFOLLOW
// and O_NONBLOCK keep the open from following or waiting, fstat refuses what is not regular.
std::string writeTemporary(const fs::path& temporary, std::string_view bytes) {
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
    if (fd < 0) return "cannot create " + temporary.string() + ": " + std::strerror(errno);
    struct stat status {};
    if (::fstat(fd, &status) != 0 || !S_ISREG(status.st_mode)) {
        ::close(fd);
        return temporary.string() + " is in the way: not a regular file";
    }
    const bool wrote = writeAll(fd, bytes);
    const int write_errno = errno;
    const bool closed = ::close(fd) == 0;
    if (!wrote || !closed) {
        const std::string why = std::strerror(wrote ? errno : write_errno);
        ::unlink(temporary.c_str());
        return why;
    }
    return {};
}

}  // namespace

std::string replaceRegularFile(const fs::path& path, std::string_view bytes) {
    if (std::string why = whyNotReplaceable(path.string()); !why.empty()) return why;
    fs::path temporary = path;
    temporary += ".radbake-tmp";
    if (std::string why = writeTemporary(temporary, bytes); !why.empty()) return why;
    if (::rename(temporary.c_str(), path.c_str()) != 0) {
        const std::string why = std::strerror(errno);
        ::unlink(temporary.c_str());
        return why;
    }
    return {};
}

bool writeFileBytes(const fs::path& path, std::string_view bytes, Diagnostics& diagnostics) {
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) {
        diagnostics.error(at(path), std::string("cannot create file: ") + std::strerror(errno));
        return false;
    }
    const size_t written = bytes.empty() ? 0 : std::fwrite(bytes.data(), 1, bytes.size(), file);
    const bool write_ok = written == bytes.size() && std::fflush(file) == 0;
    const int saved_errno = errno;
    const bool close_ok = std::fclose(file) == 0;
    if (!write_ok || !close_ok) {
        diagnostics.error(at(path), std::string("cannot write file: ") + std::strerror(write_ok ? errno : saved_errno));
        return false;
    }
    return true;
}

}  // namespace radbake
