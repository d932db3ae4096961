#pragma once
// The solver's threads: a TBB arena of a fixed size whose workers may be pinned to cores
// (on the shared 2-core machines unpinned workers were seen to share one core). Loops hand
// out indices only; every result lands in its own slot, so the output never depends on the
// thread count or on scheduling.
#include <cstddef>
#include <functional>
#include <memory>

namespace radbake {

class ParallelRunner {
public:
    // threads: 0 = all cores. pin: bind each arena slot to one core.
    ParallelRunner(int threads, bool pin);
    ~ParallelRunner();
    ParallelRunner(const ParallelRunner&) = delete;
    ParallelRunner& operator=(const ParallelRunner&) = delete;

    int threads() const { return threads_; }

    // Calls body(begin, end) on disjoint ranges covering [0, count), grain indices at least.
    void forRanges(size_t count, size_t grain, const std::function<void(size_t, size_t)>& body);

    template <class F>
    void forEach(size_t count, size_t grain, F&& f) {
        forRanges(count, grain, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) f(i);
        });
    }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int threads_ = 1;
};

}  // namespace radbake
