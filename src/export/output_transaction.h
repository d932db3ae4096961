#pragma once
// All-or-nothing output: every file of a bake is written into a private staging directory
// (inside OUTDIR when it exists, beside it when it does not) and moved into OUTDIR only when
// the whole bake succeeded (DESIGN.md section 4:
// nothing half-written is left behind). Abandoning the transaction (destructor without
// commit) removes the staging directory and any directory it had to create.
#include <filesystem>
#include <string>
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

    // Creates the staging directory (and OUTDIR's missing parents). False after reporting.
    bool begin(Diagnostics& diagnostics);

    // Where to write the output called `file_name`, a relative path with '/' separators
    // ("a.glb", "lightmaps/a_0.exr"); its directories are created in the staging directory.
    // The file is registered for commit whether or not the writer succeeds. A name that is
    // absolute, empty or has "..", "." or empty components is refused: the returned path is a
    // scratch file inside the staging directory and commit() fails naming it.
    std::filesystem::path stage(std::string_view file_name);

    // An output this run does not produce (e.g. probes.csv without --probes): an older file
    // of that name in OUTDIR is removed on commit, so OUTDIR never mixes two bakes.
    void retire(std::string_view file_name);

    // A directory of outputs this run owns (e.g. "lightmaps"): on commit, every regular file
    // directly inside OUTDIR/directory that this run did not stage is removed, and the
    // directory too when that leaves it empty, so a bake with fewer atlases (or none) leaves
    // no stale ones. Removed files are restored like replaced ones if the commit fails.
    void retireUnstagedIn(std::string_view directory);

    // The relative names passed to stage() and accepted, in staging order, without repeats.
    const std::vector<std::string>& staged() const { return staged_; }

    // Moves every staged file into OUTDIR. When OUTDIR does not exist the staging directory
    // is renamed into place in one step; otherwise files are renamed one by one and the
    // older files they replace are restored if any rename fails. A staged file with the same
    // bytes as the file it would replace leaves the old one in place, time included (so a
    // build tool's restat sees it unchanged). False after reporting.
    bool commit(Diagnostics& diagnostics);

    // After commit: how many staged outputs were new or changed (the rest kept their file).
    size_t changedCount() const { return changed_; }

    // Removes everything this transaction created; called by the destructor when not committed.
    void abandon();

    const std::filesystem::path& outDir() const { return out_dir_; }
    const std::filesystem::path& stagingDir() const { return staging_dir_; }

private:
    bool commitIntoExisting(Diagnostics& diagnostics);
    bool checkNames(Diagnostics& diagnostics) const;
    std::vector<std::string> unstagedIn(const std::string& directory) const;
    std::filesystem::path backupOf(const std::string& name) const;
    std::filesystem::path out_dir_;
    std::filesystem::path staging_dir_;
    std::vector<std::string> staged_;
    std::vector<std::string> retired_;
    std::vector<std::string> retired_dirs_;
    std::vector<std::string> rejected_;                // names stage()/retireUnstagedIn() refused
    std::vector<std::filesystem::path> created_dirs_;  // parents we made, deepest last
    bool committed_ = false;
    size_t changed_ = 0;
    int lock_fd_ = -1;          // flock on an existing OUTDIR, held from begin() (one bake at a time)
    int staging_lock_fd_ = -1;  // flock on the staging directory: it is alive (not a killed bake's)
    bool lock(Diagnostics& diagnostics);
    void unlock();
};

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

}  // namespace radbake
