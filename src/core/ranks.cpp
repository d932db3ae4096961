#include "core/ranks.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

#ifdef RADBAKE_WITH_MPI
#include <mpi.h>
#endif

namespace radbake {

namespace {

// The number of processes the launcher started, from its environment: Open MPI's mpirun, and
// PMI launchers (MPICH's Hydra, Slurm's srun); 0 when none started this process.
int launcherSize() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* value = std::getenv(name)) return std::max(1, std::atoi(value));
    return std::getenv("PMIX_RANK") ? 1 : 0;
}

}  // namespace

bool Ranks::launchedByMpi() { return launcherSize() > 0; }

const Ranks& Ranks::one() {
    static const Ranks ranks;
    return ranks;
}

bool Ranks::builtWithMpi() {
#ifdef RADBAKE_WITH_MPI
    return true;
#else
    return false;
#endif
}

#ifdef RADBAKE_WITH_MPI

namespace {

// MPI for the process's lifetime: initialised at the first use, finalised at exit.
struct MpiSession {
    int rank = 0, size = 1;
    MpiSession() {
        int provided = 0;
        // One thread at a time calls MPI (the bake's calling thread, outside parallel loops).
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        MPI_Comm_size(MPI_COMM_WORLD, &size);
    }
    ~MpiSession() {
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized) MPI_Finalize();
    }
};

// Byte counts and displacements of every rank's piece, as MPI's v-collectives take them
// (int counts: a piece is one rank's results of one loop, far below 2 GiB).
struct Pieces {
    std::vector<int> counts, offsets;
    std::string all;
    std::vector<std::string> split() const {
        std::vector<std::string> out;
        for (size_t r = 0; r < counts.size(); ++r) out.push_back(all.substr(offsets[r], counts[r]));
        return out;
    }
};

Pieces piecesOf(const std::vector<int>& counts) {
    Pieces p;
    p.counts = counts;
    size_t total = 0;
    for (int c : counts) {
        if (total + static_cast<size_t>(c) > static_cast<size_t>(INT32_MAX))
            throw std::length_error("a rank exchange of more than 2 GiB");
        p.offsets.push_back(static_cast<int>(total));
        total += static_cast<size_t>(c);
    }
    p.all.resize(total);
    return p;
}

// Adds the wall time of its lifetime to `seconds`.
class Stopwatch {
public:
    explicit Stopwatch(double& seconds) : seconds_(seconds) {}
    ~Stopwatch() { seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
    double& seconds_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

int byteCount(const std::string& mine) {
    if (mine.size() > static_cast<size_t>(INT32_MAX)) throw std::length_error("a rank exchange of more than 2 GiB");
    return static_cast<int>(mine.size());
}

}  // namespace

const Ranks& Ranks::world() {
    static const Ranks ranks = [] {
        Ranks r;
        if (!launchedByMpi()) return r;
        static MpiSession session;
        r.rank_ = session.rank;
        r.size_ = session.size;
        return r;
    }();
    return ranks;
}

std::vector<std::string> Ranks::allGather(const std::string& mine) const {
    if (size_ == 1) return {mine};
    const Stopwatch watch(exchange_seconds_);
    int count = byteCount(mine);
    std::vector<int> counts(size_);
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    Pieces p = piecesOf(counts);
    MPI_Allgatherv(mine.data(), count, MPI_BYTE, p.all.data(), p.counts.data(), p.offsets.data(), MPI_BYTE,
                   MPI_COMM_WORLD);
    exchanged_ += p.all.size() - mine.size() + mine.size() * static_cast<size_t>(size_ - 1);
    ++exchanges_;
    return p.split();
}

std::vector<std::string> Ranks::gatherToLead(const std::string& mine) const {
    if (size_ == 1) return {mine};
    const Stopwatch watch(exchange_seconds_);
    int count = byteCount(mine);
    std::vector<int> counts(size_);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    Pieces p = lead() ? piecesOf(counts) : Pieces{};
    MPI_Gatherv(mine.data(), count, MPI_BYTE, p.all.data(), p.counts.data(), p.offsets.data(), MPI_BYTE, 0,
                MPI_COMM_WORLD);
    exchanged_ += lead() ? p.all.size() - mine.size() : mine.size();
    ++exchanges_;
    return lead() ? p.split() : std::vector<std::string>{};
}

void Ranks::broadcast(std::string& bytes) const {
    if (size_ == 1) return;
    const Stopwatch watch(exchange_seconds_);
    unsigned long long size = bytes.size();
    MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    bytes.resize(size);
    exchanged_ += lead() ? bytes.size() * static_cast<size_t>(size_ - 1) : bytes.size();
    ++exchanges_;
    // In pieces: MPI counts are ints.
    constexpr size_t kPiece = size_t{1} << 30;
    for (size_t at = 0; at < bytes.size(); at += kPiece)
        MPI_Bcast(bytes.data() + at, static_cast<int>(std::min(kPiece, bytes.size() - at)), MPI_BYTE, 0,
                  MPI_COMM_WORLD);
}

void Ranks::abortAll(int code) const {
    if (size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

#else

const Ranks& Ranks::world() {
    if (launcherSize() > 1)
        throw std::runtime_error("started by mpirun, but this radbake was built without MPI (install libopenmpi-dev "
                                 "and build again)");
    static const Ranks ranks;
    return ranks;
}

std::vector<std::string> Ranks::allGather(const std::string& mine) const { return {mine}; }
std::vector<std::string> Ranks::gatherToLead(const std::string& mine) const { return {mine}; }
void Ranks::broadcast(std::string&) const {}
void Ranks::abortAll(int) const {}

#endif

}  // namespace radbake
