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
#include <optional>
#include <string>
#include <system_error>

#include "core/regular_file.h"
#include "export/json_detail.h"

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

namespace {

constexpr const char* kJournalName = ".radbake-journal";
constexpr const char* kJournalTemporaryName = ".radbake-journal.tmp";

// Backups live flat in the staging directory: "lightmaps/a_0.exr" -> ".old-lightmaps%2Fa_0.exr"
// ('%' is escaped first, so two names never share a backup).
fs::path backupPath(const fs::path& staging_dir, const std::string& name) {
    std::string flat = ".old-";
    for (char c : name) {
        if (c == '%') flat += "%25";
        else if (c == '/') flat += "%2F";
        else flat += c;
    }
    return staging_dir / flat;
}

// The lock of an OUTDIR that does not exist yet: a file beside it, ".<name>.radbake-lock".
fs::path lockFileOf(const fs::path& out_dir) {
    return out_dir.parent_path() / ("." + out_dir.filename().string() + ".radbake-lock");
}

// Whether `fd` still is the file at `path`: a lock taken on a file another bake removed (or
// replaced) in the meantime locks nothing.
bool isFileAt(int fd, const fs::path& path) {
    struct stat open_status {}, path_status {};
    return ::fstat(fd, &open_status) == 0 && ::stat(path.c_str(), &path_status) == 0 &&
           open_status.st_dev == path_status.st_dev && open_status.st_ino == path_status.st_ino;
}

bool existsNoFollow(const fs::path& path) {
    std::error_code ec;
    return fs::exists(fs::symlink_status(path, ec));
}

// `name` is a regular file in OUTDIR reached through real directories: what retire() may
// remove (never a link, nor anything a linked directory leads to).
bool isPlainFileInside(const fs::path& out_dir, const std::string& name) {
    std::error_code ec;
    fs::path path = out_dir;
    for (const fs::path& part : fs::path(name).parent_path()) {
        path /= part;
        if (!fs::is_directory(fs::symlink_status(path, ec))) return false;
    }
    return fs::is_regular_file(fs::symlink_status(out_dir / name, ec));
}

// A killed bake's lock file beside a folder that exists now (it was killed after its
// folder appeared): removed when no live bake holds it.
void removeStaleLockFile(const fs::path& out_dir) {
    const fs::path lock_file = lockFileOf(out_dir);
    const int fd = ::open(lock_file.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && isFileAt(fd, lock_file)) ::unlink(lock_file.c_str());
    ::close(fd);
}

// What a commit into an existing OUTDIR is about to do, written before it does any of it, so
// that a commit stopped at any point can be undone from the journal and the files alone.
struct Journal {
    enum class Kind { Retire, Replace, Add };  // old file moved aside; old aside and new in; new in
    struct Step {
        Kind kind = Kind::Add;
        std::string name;
    };
    std::string staging;                 // relative to OUTDIR
    std::vector<std::string> made_dirs;  // relative to OUTDIR, parents first
    std::vector<Step> steps;
};

std::string journalText(const Journal& journal) {
    using json_detail::Json;
    Json steps = Json::array();
    for (const Journal::Step& step : journal.steps)
        steps.push_back({step.kind == Journal::Kind::Retire    ? "retire"
                         : step.kind == Journal::Kind::Replace ? "replace"
                                                               : "add",
                         step.name});
    Json json;
    json["staging"] = journal.staging;
    json["made_dirs"] = journal.made_dirs;
    json["steps"] = std::move(steps);
    return json_detail::dump(json, 1) + "\n";
}

// Nullopt unless `text` is a journal this code wrote whose names all stay inside OUTDIR.
std::optional<Journal> parseJournal(const std::string& text, const fs::path& out_dir) {
    try {
        const auto json = json_detail::Json::parse(text);
        Journal journal;
        journal.staging = json.at("staging").get<std::string>();
        const std::string beside = "../." + out_dir.filename().string() + ".radbake-tmp-";
        if (journal.staging.find('/') != std::string::npos ? journal.staging.rfind(beside, 0) != 0 ||
                                                                 journal.staging.find('/', 3) != std::string::npos
                                                           : journal.staging.rfind(".radbake-tmp-", 0) != 0)
            return std::nullopt;
        for (const auto& dir : json.at("made_dirs")) {
            journal.made_dirs.push_back(dir.get<std::string>());
            if (!isSafeOutputName(journal.made_dirs.back())) return std::nullopt;
        }
        for (const auto& step : json.at("steps")) {
            const std::string kind = step.at(0).get<std::string>();
            Journal::Step parsed{kind == "retire" ? Journal::Kind::Retire
                                 : kind == "replace" ? Journal::Kind::Replace
                                                     : Journal::Kind::Add,
                                 step.at(1).get<std::string>()};
            if ((kind != "retire" && kind != "replace" && kind != "add") || !isSafeOutputName(parsed.name))
                return std::nullopt;
            journal.steps.push_back(std::move(parsed));
        }
        return journal;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

// Flushes a file's data, or a directory's entries, to the disk: a power cut after a rename
// then finds the renamed file whole, and the rename itself. Empty on success, else why.
std::string syncPath(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return path.string() + ": " + std::strerror(errno);
    const bool ok = ::fsync(fd) == 0;
    const int saved = errno;
    ::close(fd);
    return ok ? std::string() : path.string() + ": " + std::strerror(saved);
}

// Adds to `dirs` each directory of `root` that holds `name` ("a/b/c" adds root/a/b, root/a), once.
void addParentDirectories(const fs::path& root, const std::string& name, std::vector<fs::path>& dirs) {
    for (fs::path dir = fs::path(name).parent_path(); !dir.empty(); dir = dir.parent_path())
        if (std::find(dirs.begin(), dirs.end(), root / dir) == dirs.end()) dirs.push_back(root / dir);
}

// Every staged file and the directories holding them, flushed before any rename publishes them.
std::string syncStaged(const fs::path& staging_dir, const std::vector<std::string>& staged) {
    std::vector<fs::path> dirs{staging_dir};
    for (const std::string& name : staged) {
        if (std::string why = syncPath(staging_dir / name); !why.empty()) return why;
        addParentDirectories(staging_dir, name, dirs);
    }
    for (const fs::path& dir : dirs)
        if (std::string why = syncPath(dir); !why.empty()) return why;
    return {};
}

// OUTDIR, each of its directories a step of `journal` renamed into or out of, and the
// staging directory holding the backups, flushed.
void syncRenamedDirectories(const fs::path& out_dir, const fs::path& staging_dir, const Journal& journal) {
    std::vector<fs::path> dirs{out_dir, staging_dir};
    for (const Journal::Step& step : journal.steps)
        addParentDirectories(out_dir, step.name, dirs);
    for (const fs::path& dir : dirs) syncPath(dir);
}

// Written whole or not at all (a temporary renamed into place), and flushed, so that the
// renames it announces never reach the disk before it does.
std::string writeJournal(const fs::path& out_dir, const Journal& journal) {
    const fs::path temporary = out_dir / kJournalTemporaryName;
    const std::string text = journalText(journal);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0) return std::strerror(errno);
    bool ok = true;
    for (std::string_view rest = text; ok && !rest.empty();) {
        const ssize_t wrote = ::write(fd, rest.data(), rest.size());
        if (wrote < 0 && errno == EINTR) continue;
        ok = wrote > 0;
        if (ok) rest.remove_prefix(static_cast<size_t>(wrote));
    }
    ok = ok && ::fsync(fd) == 0;
    const int saved = errno;
    ok = ::close(fd) == 0 && ok;
    if (!ok || ::rename(temporary.c_str(), (out_dir / kJournalName).c_str()) != 0) {
        const std::string why = std::strerror(ok ? errno : saved);
        ::unlink(temporary.c_str());
        return why;
    }
    return syncPath(out_dir);
}

// Puts OUTDIR back as it was before the journal's commit, from wherever that commit stopped:
// each step is judged afresh from the files (is the new file still staged? is the backup
// there?), so an undo that is itself interrupted can simply be run again. Empty on success,
// else the rename that failed.
std::string undoCommit(const fs::path& out_dir, const Journal& journal, const std::function<void()>& renamed) {
    const fs::path staging = out_dir / journal.staging;
    std::error_code ec;
    for (auto it = journal.steps.rbegin(); it != journal.steps.rend(); ++it) {
        const fs::path target = out_dir / it->name, staged = staging / it->name;
        if (it->kind != Journal::Kind::Retire && !existsNoFollow(staged) && existsNoFollow(target)) {
            fs::rename(target, staged, ec);  // the new file arrived: take it back out
            if (ec) return target.string() + ": " + ec.message();
            renamed();
        }
        const fs::path backup = backupPath(staging, it->name);
        if (it->kind != Journal::Kind::Add && existsNoFollow(backup)) {
            fs::rename(backup, target, ec);
            if (ec) return target.string() + ": " + ec.message();
            renamed();
        }
    }
    for (auto it = journal.made_dirs.rbegin(); it != journal.made_dirs.rend(); ++it)
        fs::remove(out_dir / *it, ec);  // left when something else is in it
    return {};
}

}  // namespace

bool isSafeOutputName(std::string_view name) {
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

OutputTransaction::OutputTransaction(fs::path out_dir) : out_dir_(normalisedDir(out_dir)) {}

OutputTransaction::~OutputTransaction() {
    if (!committed_) abandon();
    unlock();
}

void OutputTransaction::unlock() {
    // The lock file goes while we still hold it; a bake that opened it meanwhile sees that
    // its lock is on a removed file (isFileAt) and starts again.
    if (lock_fd_ >= 0 && !lock_file_.empty()) ::unlink(lock_file_.c_str());
    lock_file_.clear();
    for (int* fd : {&lock_fd_, &staging_lock_fd_}) {
        if (*fd >= 0) ::close(*fd);  // closing releases the flock
        *fd = -1;
    }
}

bool OutputTransaction::lock(Diagnostics& diagnostics) {
    // An existing OUTDIR is locked itself (flock on the directory); a new one through a lock
    // file beside it, so that two bakes racing to create it cannot both go ahead. The kernel
    // releases either when a bake dies, even by SIGKILL. Never waits: a second bake is refused.
    for (int attempt = 0; attempt < 16; ++attempt) {
        std::error_code ec;
        const bool exists = fs::is_directory(out_dir_, ec);
        const fs::path target = exists ? out_dir_ : lockFileOf(out_dir_);
        const int fd = exists ? ::open(target.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)
                              : ::open(target.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
        if (fd < 0 && errno == ENOENT) continue;  // removed since we looked: look again
        if (fd < 0) {
            diagnostics.error(at(target), std::string("cannot lock the output directory: ") + std::strerror(errno));
            return false;
        }
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            const int saved = errno;
            ::close(fd);
            diagnostics.error(at(out_dir_), saved == EWOULDBLOCK
                                                ? std::string("another bake is writing into this directory; nothing "
                                                              "written (bake into another directory, or after it)")
                                                : std::string("cannot lock the output directory: ") +
                                                      std::strerror(saved));
            return false;
        }
        const bool settled = isFileAt(fd, target) && (exists || !fs::exists(out_dir_, ec));
        if (!settled) {
            // Replaced or removed while we locked it, or another bake's folder appeared:
            // what is to be locked has changed.
            if (!exists && isFileAt(fd, target)) ::unlink(target.c_str());
            ::close(fd);
            continue;
        }
        lock_fd_ = fd;
        if (!exists) lock_file_ = target;
        else removeStaleLockFile(out_dir_);
        return true;
    }
    diagnostics.error(at(out_dir_), "cannot lock the output directory: it keeps changing");
    return false;
}

namespace {

// A commit a killed bake left half done (its journal in OUTDIR) is undone, under the lock,
// before this bake looks at anything else. False after reporting: then the journal and the
// backups it needs are kept.
bool recoverInterruptedCommit(const fs::path& out_dir, const std::function<void()>& renamed,
                              Diagnostics& diagnostics) {
    const fs::path path = out_dir / kJournalName;
    ::unlink((out_dir / kJournalTemporaryName).c_str());  // a journal never finished: nothing was moved
    if (!existsNoFollow(path)) return true;
    std::string why;
    const std::optional<std::string> text = readRegularFile(path.string(), why);
    std::optional<Journal> journal = text ? parseJournal(*text, out_dir) : std::nullopt;
    std::error_code ec;
    if (journal && !fs::is_directory(out_dir / journal->staging, ec)) why = "its staging directory is gone";
    else if (!journal && why.empty()) why = "not a journal radbake wrote";
    if (why.empty()) why = undoCommit(out_dir, *journal, renamed);
    if (!why.empty()) {
        diagnostics.error(at(path), "cannot undo the interrupted commit this journal records (" + why +
                                        "); nothing written: restore the folder and remove the journal");
        return false;
    }
    ::unlink(path.c_str());  // the older bake is whole again
    fs::remove_all(out_dir / journal->staging, ec);
    diagnostics.note(at(out_dir), "a bake was killed while committing here: its changes were undone");
    return true;
}

}  // namespace

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
    size_t renames = 0;
    const auto renamed = [&] {
        if (rename_hook_) rename_hook_(++renames);
    };
    if (!lock(diagnostics) ||
        (fs::is_directory(out_dir_, ec) && !recoverInterruptedCommit(out_dir_, renamed, diagnostics))) {
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
    if (!lock_file_.empty()) registerSignalPath(lock_file_);  // ours while we hold it
    return true;
}

fs::path OutputTransaction::stage(std::string_view file_name) {
    const std::string name(file_name);
    if (!isSafeOutputName(name)) {
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
    registerSignalPath(backupPath(staging_dir_, name));
    return path;
}

void OutputTransaction::retire(std::string_view file_name) {
    const std::string name(file_name);
    if (!isSafeOutputName(name)) {
        rejected_.push_back(name);
        return;
    }
    if (std::find(retired_.begin(), retired_.end(), name) != retired_.end()) return;
    retired_.push_back(name);
    registerSignalPath(backupPath(staging_dir_, name));
}

bool OutputTransaction::checkNames(Diagnostics& diagnostics) const {
    for (const std::string& name : rejected_)
        diagnostics.error(at(out_dir_), "internal: output name '" + name +
                                            "' is not a relative path inside the output directory");
    return rejected_.empty();
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
    if (const std::string why = syncStaged(staging_dir_, staged_); !why.empty()) {
        diagnostics.error(at(out_dir_), "cannot flush the outputs to disk: " + why);
        return false;
    }
    if (!fs::exists(out_dir_, ec)) {
        // A new OUTDIR appears in one atomic step, complete (the lock file keeps other bakes out).
        changed_ = staged_.size();
        fs::rename(staging_dir_, out_dir_, ec);
        if (ec) {
            diagnostics.error(at(out_dir_), "cannot move outputs into place: " + ec.message());
            return false;
        }
        syncPath(out_dir_.parent_path().empty() ? fs::path(".") : out_dir_.parent_path());
        forgetSignalPaths();
        committed_ = true;
        staging_dir_.clear();
        unlock();
        return true;
    }
    // OUTDIR appeared since begin() (made by hand: a bake would have needed our lock file):
    // lock it too before changing it.
    if (!lock_file_.empty()) {
        const int file_lock = lock_fd_;
        const fs::path lock_file = lock_file_;
        lock_fd_ = -1;
        lock_file_.clear();
        const bool locked = lock(diagnostics);
        ::unlink(lock_file.c_str());
        ::close(file_lock);
        if (!locked) return false;
    }
    if (!commitIntoExisting(diagnostics)) return false;
    committed_ = true;
    fs::remove_all(staging_dir_, ec);  // only backups of the replaced files remain there
    staging_dir_.clear();
    removeEmptiedDirectories();
    unlock();
    return true;
}

// Directories a retired file leaves empty go too (a bake now without lightmaps leaves no
// empty lightmaps/), deepest first; OUTDIR itself stays.
void OutputTransaction::removeEmptiedDirectories() const {
    std::error_code ec;
    for (const std::string& name : retired_) {
        for (fs::path dir = fs::path(name).parent_path(); !dir.empty(); dir = dir.parent_path()) {
            const fs::path path = out_dir_ / dir;
            if (!fs::is_directory(fs::symlink_status(path, ec)) || !fs::is_empty(path, ec) || ec) break;
            fs::remove(path, ec);
        }
    }
}

bool OutputTransaction::commitIntoExisting(Diagnostics& diagnostics) {
    // The whole plan first, checked before anything moves; the journal records it.
    Journal journal;
    journal.staging = staging_dir_.lexically_relative(out_dir_).generic_string();
    changed_ = 0;
    std::error_code ec;
    for (const std::string& name : retired_)
        if (std::find(staged_.begin(), staged_.end(), name) == staged_.end() && isPlainFileInside(out_dir_, name))
            journal.steps.push_back({Journal::Kind::Retire, name});
    for (const std::string& name : staged_) {
        // Sub-directories ("lightmaps/") are made on the way, undone with the rest.
        fs::path relative;
        for (const fs::path& part : fs::path(name).parent_path()) {
            relative /= part;
            const fs::path dir = out_dir_ / relative;
            if (fs::is_directory(dir, ec)) continue;
            if (existsNoFollow(dir)) {
                diagnostics.error(at(dir), "cannot create output directory: a file is in the way");
                return false;
            }
            if (std::find(journal.made_dirs.begin(), journal.made_dirs.end(), relative.generic_string()) ==
                journal.made_dirs.end())
                journal.made_dirs.push_back(relative.generic_string());
        }
        const fs::path target = out_dir_ / name;
        const bool had_old = existsNoFollow(target);
        if (had_old && sameBytes(staging_dir_ / name, target)) continue;  // unchanged: keep the old file
        ++changed_;
        journal.steps.push_back({had_old ? Journal::Kind::Replace : Journal::Kind::Add, name});
    }
    if (journal.steps.empty()) return true;
    // From here a signal leaves the staging directory alone: the journal needs its backups.
    forgetSignalPaths();
    if (const std::string why = writeJournal(out_dir_, journal); !why.empty()) {
        diagnostics.error(at(out_dir_ / kJournalName), "cannot write the commit's journal: " + why);
        return false;
    }
    size_t renames = 0;
    const auto renamed = [&] {
        if (rename_hook_) rename_hook_(++renames);
    };
    std::string failure;
    for (const std::string& dir : journal.made_dirs) {
        if (!fs::create_directory(out_dir_ / dir, ec) && !fs::is_directory(out_dir_ / dir)) {
            failure = "cannot create output directory " + (out_dir_ / dir).string() + ": " + ec.message();
            break;
        }
    }
    for (size_t i = 0; failure.empty() && i < journal.steps.size(); ++i) {
        const Journal::Step& step = journal.steps[i];
        const fs::path target = out_dir_ / step.name;
        if (step.kind != Journal::Kind::Add) {
            fs::rename(target, backupPath(staging_dir_, step.name), ec);
            if (ec) failure = "cannot move older output " + target.string() + " aside: " + ec.message();
            else renamed();
        }
        if (failure.empty() && step.kind != Journal::Kind::Retire) {
            fs::rename(staging_dir_ / step.name, target, ec);
            if (ec) failure = "cannot move output " + target.string() + " into place: " + ec.message();
            else renamed();
        }
    }
    if (failure.empty()) {
        // The renames reach the disk before the journal that could undo them goes.
        syncRenamedDirectories(out_dir_, staging_dir_, journal);
        ::unlink((out_dir_ / kJournalName).c_str());  // the commit point: the new bake is whole
        syncPath(out_dir_);
        return true;
    }
    diagnostics.error(at(out_dir_), failure);
    if (const std::string why = undoCommit(out_dir_, journal, [] {}); !why.empty()) {
        // The journal and the backups stay for the next bake to finish the undo.
        diagnostics.error(at(out_dir_), "cannot restore the older outputs yet (" + why + "); the next bake will");
        staging_dir_.clear();
        return false;
    }
    ::unlink((out_dir_ / kJournalName).c_str());
    return false;
}

void OutputTransaction::abandon() {
    if (!staging_dir_.empty()) forgetSignalPaths();
    std::error_code ec;
    if (!staging_dir_.empty()) fs::remove_all(staging_dir_, ec);
    staging_dir_.clear();
    unlock();  // the lock file beside a new OUTDIR goes before the parents it may be in
    // Deepest first; fs::remove leaves a directory someone else has put files into.
    for (auto it = created_dirs_.rbegin(); it != created_dirs_.rend(); ++it) fs::remove(*it, ec);
    created_dirs_.clear();
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
std::string writeTemporary(const fs::path& temporary, std::span<const std::string_view> pieces) {
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
    if (fd < 0) return "cannot create " + temporary.string() + ": " + std::strerror(errno);
    struct stat status {};
    if (::fstat(fd, &status) != 0 || !S_ISREG(status.st_mode)) {
        ::close(fd);
        return temporary.string() + " is in the way: not a regular file";
    }
    bool wrote = true;
    for (size_t k = 0; k < pieces.size() && wrote; ++k) wrote = writeAll(fd, pieces[k]);
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
    return replaceRegularFile(path, std::span<const std::string_view>(&bytes, 1));
}

std::string replaceRegularFile(const fs::path& path, std::span<const std::string_view> pieces) {
    if (std::string why = whyNotReplaceable(path.string()); !why.empty()) return why;
    fs::path temporary = path;
    temporary += ".radbake-tmp";
    if (std::string why = writeTemporary(temporary, pieces); !why.empty()) return why;
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
