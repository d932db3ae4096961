#pragma once
// The processes one bake runs on: the ranks `mpirun -np N radbake ...` starts (MPI_COMM_WORLD),
// or this process alone. Every rank holds the scene and runs the same steps; a loop shared
// between ranks computes its share of the items and the ranks then swap results, so every
// rank ends each loop with every item's result, bit for bit what one process computes.
// core/ranks.cpp is the only file that includes MPI (optional: without it, one rank).
#include <cstddef>
#include <string>
#include <vector>

namespace radbake {

class Ranks {
public:
    Ranks() = default;  // this process alone: rank 0 of 1
    // The processes mpirun started, joined at the first call; this process alone when it was not
    // started by an MPI launcher. Throws when it was, but radbake was built without MPI.
    static const Ranks& world();
    static const Ranks& one();  // this process alone
    // True when an MPI launcher started this process (its environment says so).
    static bool launchedByMpi();
    static bool builtWithMpi();

    int rank() const { return rank_; }
    int size() const { return size_; }
    bool lead() const { return rank_ == 0; }  // the rank that reads and writes files

    // Every rank's bytes, in rank order, on every rank (collective).
    std::vector<std::string> allGather(const std::string& mine) const;
    // Every rank's bytes, in rank order, on the lead; empty on the others (collective).
    std::vector<std::string> gatherToLead(const std::string& mine) const;
    // The lead's bytes on every rank (collective).
    void broadcast(std::string& bytes) const;
    // Ends every rank's process with `code` (one rank failed while the others may be waiting
    // in a collective). Returns only with one rank.
    void abortAll(int code) const;

    // Bytes this rank has sent and received in exchanges so far (what crosses the network), and
    // the exchanges (collectives) that carried them.
    unsigned long long exchangedBytes() const { return exchanged_; }
    unsigned long long exchanges() const { return exchanges_; }
    // Wall seconds this rank spent in exchanges (waiting for the slowest rank included), and
    // computing its share of shared work (as its callers report it): with the bake's wall time,
    // what the scale model reads (tools/scale_model.py).
    double exchangeSeconds() const { return exchange_seconds_; }
    double sharedSeconds() const { return shared_seconds_; }
    void addSharedSeconds(double seconds) const { shared_seconds_ += seconds; }

    // Items [0, count) are shared in blocks of `block`, dealt round-robin: block b is rank
    // b mod size's (neighbouring items cost alike, so each rank gets a like mix).
    bool owns(size_t item, size_t block) const {
        return size_ == 1 || (item / block) % static_cast<size_t>(size_) == static_cast<size_t>(rank_);
    }

private:
    int rank_ = 0, size_ = 1;
    // One thread at a time exchanges and reports.
    mutable unsigned long long exchanged_ = 0, exchanges_ = 0;
    mutable double exchange_seconds_ = 0.0, shared_seconds_ = 0.0;
};

}  // namespace radbake
