#include "core/parallel.h"

#include <sched.h>

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <algorithm>
#include <exception>
#include <mutex>

namespace radbake {
namespace {

// Pins each thread that enters the arena to the core of its slot, and gives it back its
// old mask when it leaves (the calling thread takes part too).
class PinningObserver : public tbb::task_scheduler_observer {
public:
    PinningObserver(tbb::task_arena& arena, int cores) : tbb::task_scheduler_observer(arena), cores_(cores) {
        observe(true);
    }
    ~PinningObserver() override { observe(false); }

    void on_scheduler_entry(bool) override {
        const int slot = tbb::this_task_arena::current_thread_index();
        if (slot < 0 || cores_ <= 0) return;
        saved().valid = sched_getaffinity(0, sizeof(cpu_set_t), &saved().mask) == 0;
        cpu_set_t mask;
        CPU_ZERO(&mask);
        CPU_SET(slot % cores_, &mask);
        sched_setaffinity(0, sizeof(mask), &mask);
    }
    void on_scheduler_exit(bool) override {
        if (saved().valid) sched_setaffinity(0, sizeof(cpu_set_t), &saved().mask);
        saved().valid = false;
    }

private:
    struct Saved {
        cpu_set_t mask;
        bool valid = false;
    };
    static Saved& saved() {
        thread_local Saved s;
        return s;
    }
    int cores_;
};

}  // namespace

struct ParallelRunner::Impl {
    tbb::task_arena arena;
    std::unique_ptr<PinningObserver> observer;
    explicit Impl(int threads) : arena(threads) {}
};

ParallelRunner::ParallelRunner(Threading threading, const std::atomic<bool>* cancel)
    : cancel_(cancel), ranks_(threading.ranks) {
    const int cores = tbb::info::default_concurrency();
    threads_ = threading.threads > 0 ? threading.threads : cores;
    impl_ = std::make_unique<Impl>(threads_);
    // Pin only when each slot can have a core of its own.
    if (threading.pin && threads_ > 1 && threads_ <= cores) {
        impl_->arena.initialize();
        impl_->observer = std::make_unique<PinningObserver>(impl_->arena, cores);
    }
}

ParallelRunner::~ParallelRunner() = default;

void ParallelRunner::forRanges(size_t count, size_t grain, const std::function<void(size_t, size_t)>& body) {
    if (count == 0 || cancelled()) return;
    if (threads_ == 1 || count <= grain) {
        // Still in grain-sized pieces, so a cancel is seen within one piece.
        const size_t step = std::max<size_t>(grain, 1);
        for (size_t begin = 0; begin < count && !cancelled(); begin += step) body(begin, std::min(count, begin + step));
        return;
    }
    // Exceptions must not escape a TBB task unseen: keep the first, rethrow it here (the
    // solver's boundary catches it).
    std::exception_ptr failure;
    std::mutex failure_mutex;
    impl_->arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count, grain ? grain : 1),
                          [&](const tbb::blocked_range<size_t>& range) {
                              if (cancelled()) return;
                              try {
                                  body(range.begin(), range.end());
                              } catch (...) {
                                  std::lock_guard<std::mutex> lock(failure_mutex);
                                  if (!failure) failure = std::current_exception();
                              }
                          });
    });
    if (failure) std::rethrow_exception(failure);
}

void ParallelRunner::execute(const std::function<void()>& work) {
    impl_->arena.execute(work);  // also with one thread: a nested TBB loop must not spread out
}

}  // namespace radbake
