#include "core/progress.h"

#include <cstdio>

namespace radbake {

namespace {
double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

Progress::Progress(bool show) : show_(show) {}

Progress::~Progress() { endPhase(); }

void Progress::beginPhase(std::string_view name) {
    endPhase();
    current_ = name;
    phase_start_ = std::chrono::steady_clock::now();
    fraction_ = 0.0;
    last_draw_ns_ = 0;
}

void Progress::update(double fraction) {
    fraction_.store(fraction, std::memory_order_relaxed);
    if (!show_) return;
    // Redraw at most ten times a second; whichever thread wins the exchange draws.
    const int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now() - phase_start_).count();
    int64_t last = last_draw_ns_.load(std::memory_order_relaxed);
    if (now - last < 100'000'000) return;
    if (last_draw_ns_.compare_exchange_strong(last, now)) draw(false);
}

void Progress::endPhase() {
    if (current_.empty()) return;
    phases_.emplace_back(current_, secondsSince(phase_start_));
    if (show_) draw(true);
    current_.clear();
}

void Progress::draw(bool final_line) {
    const double elapsed = secondsSince(phase_start_);
    const double f = fraction_.load(std::memory_order_relaxed);
    if (final_line) {
        std::fprintf(stderr, "\r\033[K%-12s done in %.2f s\n", current_.c_str(), elapsed);
    } else if (f > 0.01) {
        std::fprintf(stderr, "\r\033[K%-12s %5.1f %%  elapsed %.1f s  remaining ~%.1f s", current_.c_str(),
                     100.0 * f, elapsed, elapsed * (1.0 - f) / f);
    } else {
        std::fprintf(stderr, "\r\033[K%-12s elapsed %.1f s", current_.c_str(), elapsed);
    }
    std::fflush(stderr);
}

}  // namespace radbake
