#pragma once
// Every phase's threads: a TBB arena of a fixed size, owned by the bake that made it (no
// process-wide limit, so a host program's own TBB work and a second bake are untouched).
// Workers may be pinned to cores when asked (on the shared 2-core machines unpinned workers
// were seen to share one core). Loops hand out indices only; every result lands in its own
// slot, so the output never depends on the thread count or on scheduling.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>

#include "core/binary_records.h"
#include "core/ranks.h"

namespace radbake {

// How many threads a bake's phases use. A library default: all cores, not pinned.
struct Threading {
    int threads = 0;   // 0: all cores
    bool pin = false;  // bind each worker to one core (only when each can have its own)
    const Ranks* ranks = nullptr;  // the processes that share the loops marked shared; nullptr: this one
};

class ParallelRunner {
public:
    // `cancel`, when given, is polled between ranges: once it is set, the ranges not yet
    // started are skipped (the caller checks it and discards the partial result).
    explicit ParallelRunner(Threading threading, const std::atomic<bool>* cancel = nullptr);
    ParallelRunner(int threads, bool pin) : ParallelRunner(Threading{threads, pin}) {}
    ~ParallelRunner();
    ParallelRunner(const ParallelRunner&) = delete;
    ParallelRunner& operator=(const ParallelRunner&) = delete;

    int threads() const { return threads_; }
    const Ranks& ranks() const { return ranks_ ? *ranks_ : Ranks::one(); }
    bool cancelled() const { return cancel_ && cancel_->load(std::memory_order_relaxed); }

    // Calls body(begin, end) on disjoint ranges covering [0, count), grain indices at least.
    void forRanges(size_t count, size_t grain, const std::function<void(size_t, size_t)>& body);

    template <class F>
    void forEach(size_t count, size_t grain, F&& f) {
        forRanges(count, grain, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) f(i);
        });
    }

    // A loop shared between ranks: compute(i) for this rank's share of [0, count) (blocks of
    // `block` items, Ranks::owns) on this runner's threads; then encode(Writer&, i) writes each
    // own item's result and decode(Reader&, i) reads every other rank's, in the same order. With
    // one rank, forEach(count, block, compute). Collective: every rank calls it with the same count.
    template <class Compute, class Encode, class Decode>
    void forEachShared(size_t count, size_t block, Compute&& compute, Encode&& encode, Decode&& decode) {
        const Ranks& r = ranks();
        if (r.size() == 1) return forEach(count, block, compute);
        block = block > 0 ? block : 1;
        const size_t blocks = (count + block - 1) / block, size = static_cast<size_t>(r.size());
        // Rank k owns blocks k, k + size, k + 2 size, ...: its j-th is block k + j size.
        const auto ownBlocks = [&](size_t rank) { return blocks > rank ? (blocks - rank + size - 1) / size : 0; };
        const auto forBlock = [&](size_t rank, size_t j, auto&& f) {
            for (size_t i = (rank + j * size) * block, end = std::min(count, i + block); i < end; ++i) f(i);
        };
        const auto forOwn = [&](size_t rank, auto&& f) {
            for (size_t j = 0; j < ownBlocks(rank); ++j) forBlock(rank, j, f);
        };
        const size_t me = static_cast<size_t>(r.rank());
        const auto start = std::chrono::steady_clock::now();
        forEach(ownBlocks(me), 1, [&](size_t j) { forBlock(me, j, compute); });
        r.addSharedSeconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        Writer writer;
        forOwn(me, [&](size_t i) { encode(writer, i); });
        const std::vector<std::string> all = r.allGather(writer.bytes);
        for (size_t rank = 0; rank < size; ++rank) {
            if (rank == me) continue;
            Reader reader{all[rank]};
            forOwn(rank, [&](size_t i) { decode(reader, i); });
            if (!reader.ok || reader.at != all[rank].size())
                throw std::runtime_error("rank " + std::to_string(rank) + " sent results that do not fit its share");
        }
    }
    // forEachShared for results that are trivially copyable values, one per item in `slots`.
    template <class T, class Compute>
    void forEachSharedSlot(std::vector<T>& slots, size_t block, Compute&& compute) {
        forEachShared(
            slots.size(), block, compute, [&](Writer& w, size_t i) { w.value(slots[i]); },
            [&](Reader& r, size_t i) { r.value(slots[i]); });
    }

    // Runs `work` inside this runner's arena, so a library's own TBB loops in it (Embree's
    // BVH build) use this runner's threads and no more.
    void execute(const std::function<void()>& work);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int threads_ = 1;
    const std::atomic<bool>* cancel_ = nullptr;
    const Ranks* ranks_ = nullptr;
};

}  // namespace radbake
