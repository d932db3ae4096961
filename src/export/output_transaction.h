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

    // Where to write the output called `file_name` (a plain name, no directories); the file
    // is registered for commit whether or not the writer succeeds.
    std::filesystem::path stage(std::string_view file_name);

    // An output this run does not produce (e.g. probes.csv without --probes): an older file
    // of that name in OUTDIR is removed on commit, so OUTDIR never mixes two bakes.
    void retire(std::string_view file_name);

    // Moves every staged file into OUTDIR. When OUTDIR does not exist the staging directory
    // is renamed into place in one step; otherwise files are renamed one by one and the
    // older files they replace are restored if any rename fails. False after reporting.
    bool commit(Diagnostics& diagnostics);

    // Removes everything this transaction created; called by the destructor when not committed.
    void abandon();

    const std::filesystem::path& outDir() const { return out_dir_; }
    const std::filesystem::path& stagingDir() const { return staging_dir_; }

private:
    bool commitIntoExisting(Diagnostics& diagnostics);
    std::filesystem::path out_dir_;
    std::filesystem::path staging_dir_;
    std::vector<std::string> staged_;
    std::vector<std::string> retired_;
    std::vector<std::filesystem::path> created_dirs_;  // parents we made, deepest last
    bool committed_ = false;
};

// On SIGINT/SIGTERM/SIGHUP, removes the staged files and the staging directory of the
// transaction begun most recently (and not yet committed or abandoned), then dies of the
// signal as usual: an interrupted content build leaves no temporary directory behind.
void cleanUpStagingOnSignals();

// Writes `bytes` to `path` (create or truncate) and checks every step, including the close.
bool writeFileBytes(const std::filesystem::path& path, std::string_view bytes, Diagnostics& diagnostics);

}  // namespace radbake
