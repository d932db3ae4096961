#pragma once
// All-or-nothing output: every file of a bake is written into a private staging directory
// (inside OUTDIR when it exists, beside it when it does not) and moved into OUTDIR only when
// the whole bake succeeded (DESIGN.md section 4: nothing half-written is left behind).
// Abandoning the transaction (destructor without commit) removes the staging directory and
// any directory it had to create. The folder is locked from begin() to the end, and a commit
// survives a kill at any point: the next begin() restores the older outputs.
#include <filesystem>
#include <functional>
#include <string>
#include <span>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"

namespace radbake {

class OutputTransaction {
public:
    explicit OutputTransaction(std::filesystem::path out_dir);
    ~OutputTransaction();
    OutputTransaction(const OutputTransaction&) = delete;
    OutputTransaction& operator=(const OutputTransaction&) = delete;

    // Locks OUTDIR (one bake at a time per folder: a second is refused at once, never kept
    // waiting, also for a folder that does not exist yet), undoes a commit a killed bake left
    // half done (its journal), removes killed bakes' staging directories and creates this
    // one's (and OUTDIR's missing parents). Call it before any work, so that a refused bake
    // costs nothing. False after reporting.
    bool begin(Diagnostics& diagnostics);

    // Where to write the output called `file_name`, a relative path with '/' separators
    // ("a.glb", "lightmaps/a_0.exr"); its directories are created in the staging directory.
    // The file is registered for commit whether or not the writer succeeds. A name that is
    // absolute, empty or has "..", "." or empty components is refused: the returned path is a
    // scratch file inside the staging directory and commit() fails naming it.
    std::filesystem::path stage(std::string_view file_name);

    // A file an earlier bake wrote (its manifest lists it) that this one may not write: on
    // commit it is removed unless this bake stages it, and its directory too when that leaves
    // it empty. Only a regular file is removed (a link or a directory is kept); files nobody
    // retired are never touched. Removed files are restored like replaced ones if the commit
    // fails.
    void retire(std::string_view file_name);

    // The relative names passed to stage() and accepted, in staging order, without repeats.
    const std::vector<std::string>& staged() const { return staged_; }

    // Moves every staged file into OUTDIR. When OUTDIR does not exist the staging directory
    // is renamed into place in one step; otherwise the renames are first written to a journal
    // in OUTDIR, then done one by one, and the older files they replace are restored if any
    // fails (or, after a kill, by the next begin()). A staged file with the same bytes as the
    // file it would replace leaves the old one in place, time included (so a build tool's
    // restat sees it unchanged). False after reporting.
    bool commit(Diagnostics& diagnostics);

    // After commit: how many staged outputs were new or changed (the rest kept their file).
    size_t changedCount() const { return changed_; }

    // Removes everything this transaction created and releases the lock; called by the
    // destructor when not committed.
    void abandon();

    const std::filesystem::path& outDir() const { return out_dir_; }
    const std::filesystem::path& stagingDir() const { return staging_dir_; }

    // For tests: called with 1, 2, ... after each rename of a commit into an existing folder
    // (and of an interrupted commit's undoing), so a test can die there as a kill would.
    void setRenameHookForTesting(std::function<void(size_t)> hook) { rename_hook_ = std::move(hook); }

private:
    bool commitIntoExisting(Diagnostics& diagnostics);
    bool checkNames(Diagnostics& diagnostics) const;
    void removeEmptiedDirectories() const;
    std::filesystem::path out_dir_;
    std::filesystem::path staging_dir_;
    std::vector<std::string> staged_;
    std::vector<std::string> retired_;
    std::vector<std::string> rejected_;                // names stage()/retire() refused
    std::vector<std::filesystem::path> created_dirs_;  // parents we made, deepest last
    bool committed_ = false;
    size_t changed_ = 0;
    // flock held from begin() to the end: on OUTDIR itself when it exists, else on a lock
    // file beside it (lock_file_), removed on release.
    int lock_fd_ = -1;
    std::filesystem::path lock_file_;
    int staging_lock_fd_ = -1;  // flock on the staging directory: it is alive (not a killed bake's)
    std::function<void(size_t)> rename_hook_;
    bool lock(Diagnostics& diagnostics);
    void unlock();
};

// A relative name with '/' separators that cannot leave the directory it is relative to
// (what stage() and retire() accept).
bool isSafeOutputName(std::string_view name);

// On SIGINT/SIGTERM/SIGHUP, removes the staged files and the staging directory of the
// transaction begun most recently (and not yet committed or abandoned), then dies of the
// signal as usual: an interrupted content build leaves no temporary directory behind. For a
// program, not the library: a host that installs its own handlers does not call this.
void cleanUpStagingOnSignals();

// Writes `bytes` to `path` (create or truncate) and checks every step, including the close.
bool writeFileBytes(const std::filesystem::path& path, std::string_view bytes, Diagnostics& diagnostics);

// Replaces the file at `path` with `bytes`, whole or not at all: written to PATH.radbake-tmp,
// then renamed over it. Only a regular file (or nothing) is replaced: a directory, FIFO,
// device or socket at `path` is refused and kept. Empty on success, else why it failed (the
// real cause, never "Success"); no temporary is left behind either way.
std::string replaceRegularFile(const std::filesystem::path& path, std::string_view bytes);
// The same with the bytes given in pieces, written one after the other (a large file straight
// from the memory that holds it, without a copy).
std::string replaceRegularFile(const std::filesystem::path& path, std::span<const std::string_view> pieces);

}  // namespace radbake
