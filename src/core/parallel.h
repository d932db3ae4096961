#pragma once
// Every phase's threads: a TBB arena of a fixed size, owned by the bake that made it (no
// process-wide limit, so a host program's own TBB work and a second bake are untouched).
// Workers may be pinned to cores when asked (on the shared 2-core machines unpinned workers
// were seen to share one core). Loops hand out indices only; every result lands in its own
// slot, so the output never depends on the thread count or on scheduling.
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>

namespace radbake {

// How many threads a bake's phases use. A library default: all cores, not pinned.
struct Threading {
    int threads = 0;   // 0: all cores
    bool pin = false;  // bind each worker to one core (only when each can have its own)
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
    bool cancelled() const { return cancel_ && cancel_->load(std::memory_order_relaxed); }

    // Calls body(begin, end) on disjoint ranges covering [0, count), grain indices at least.
    void forRanges(size_t count, size_t grain, const std::function<void(size_t, size_t)>& body);

    template <class F>
    void forEach(size_t count, size_t grain, F&& f) {
        forRanges(count, grain, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) f(i);
        });
    }

    // Runs `work` inside this runner's arena, so a library's own TBB loops in it (Embree's
    // BVH build) use this runner's threads and no more.
    void execute(const std::function<void()>& work);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int threads_ = 1;
    const std::atomic<bool>* cancel_ = nullptr;
};

}  // namespace radbake
