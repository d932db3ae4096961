#include "core/progress.h"

#include <algorithm>
#include <cstdio>

namespace radbake {

namespace {
// A phase logs its percentages only once it has run this long: short phases log their end only.
constexpr int64_t kLogAfterNs = 2'000'000'000;

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// "42.0 s" below two minutes, "3 min 05 s" above: long bakes read better in minutes.
std::string duration(double seconds) {
    char buffer[32];
    if (seconds < 120.0) {
        std::snprintf(buffer, sizeof buffer, "%.1f s", seconds);
    } else {
        const long whole = static_cast<long>(seconds);
        std::snprintf(buffer, sizeof buffer, "%ld min %02ld s", whole / 60, whole % 60);
    }
    return buffer;
}
}  // namespace

Progress::Progress(bool show)
    : show_(show), start_(std::chrono::steady_clock::now()), phase_start_(start_) {}

Progress::Progress(ProgressStyle style) : Progress(style == ProgressStyle::Terminal) {
    lines_ = style == ProgressStyle::Lines;
}

Progress::~Progress() { endPhase(); }

double Progress::totalSeconds() const { return secondsSince(start_); }

void Progress::beginPhase(std::string_view name) {
    endPhase();
    current_ = name;
    phase_start_ = std::chrono::steady_clock::now();
    fraction_ = 0.0;
    last_draw_ns_ = 0;
    logged_tenths_ = 0;
    if (sink_) notify(false, 0.0);
    if (show_) draw(false);
}

void Progress::notify(bool phase_done, double phase_seconds) {
    ProgressEvent event;
    event.phase = current_;
    event.fraction = phase_done ? 1.0 : fraction_.load(std::memory_order_relaxed);
    event.phase_seconds = phase_seconds;
    event.total_seconds = totalSeconds();
    event.phase_done = phase_done;
    sink_(event);
}

void Progress::update(double fraction) {
    fraction_.store(std::clamp(fraction, 0.0, 1.0), std::memory_order_relaxed);
    if (!show_ && !sink_ && !lines_) return;
    // Redraw at most ten times a second; whichever thread wins the exchange draws.
    const int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now() - phase_start_).count();
    int64_t last = last_draw_ns_.load(std::memory_order_relaxed);
    if (now - last < 100'000'000) return;
    if (!last_draw_ns_.compare_exchange_strong(last, now)) return;
    if (sink_) notify(false, 1e-9 * static_cast<double>(now));
    if (show_) draw(false);
    if (lines_ && now >= kLogAfterNs) logLine(false);
}

void Progress::endPhase() {
    if (current_.empty()) return;
    phases_.emplace_back(current_, secondsSince(phase_start_));
    if (sink_) notify(true, phases_.back().second);
    if (show_) draw(true);
    if (lines_) logLine(true);
    current_.clear();
}

void Progress::printLine(std::string_view line) {
    std::lock_guard<std::mutex> lock(draw_mutex_);
    if (line_open_) std::fputs("\r\033[K", stderr);
    std::fwrite(line.data(), 1, line.size(), stderr);
    std::fputc('\n', stderr);
    line_open_ = false;
    std::fflush(stderr);
}

void Progress::draw(bool final_line) {
    std::lock_guard<std::mutex> lock(draw_mutex_);
    const double elapsed = secondsSince(phase_start_);
    const double total = secondsSince(start_);
    const double f = fraction_.load(std::memory_order_relaxed);
    if (final_line) {
        std::fprintf(stderr, "\r\033[K%-12s done in %s\n", current_.c_str(), duration(elapsed).c_str());
        line_open_ = false;
    } else if (f > 0.01) {
        std::fprintf(stderr, "\r\033[K%-12s %5.1f %%  elapsed %s (total %s)  remaining ~%s", current_.c_str(),
                     100.0 * f, duration(elapsed).c_str(), duration(total).c_str(),
                     duration(elapsed * (1.0 - f) / f).c_str());
        line_open_ = true;
    } else {
        std::fprintf(stderr, "\r\033[K%-12s elapsed %s (total %s)", current_.c_str(), duration(elapsed).c_str(),
                     duration(total).c_str());
        line_open_ = true;
    }
    std::fflush(stderr);
}

void Progress::logLine(bool final_line) {
    std::lock_guard<std::mutex> lock(draw_mutex_);
    const double elapsed = secondsSince(phase_start_);
    const double total = secondsSince(start_);
    if (final_line) {
        std::fprintf(stderr, "radbake: %s done in %s (total %s)\n", current_.c_str(), duration(elapsed).c_str(),
                     duration(total).c_str());
    } else {
        const double f = fraction_.load(std::memory_order_relaxed);
        const int tenths = static_cast<int>(10.0 * f);
        if (tenths <= logged_tenths_ || tenths >= 10) return;
        logged_tenths_ = tenths;
        std::fprintf(stderr, "radbake: %s %d %%, %s in the phase (total %s), about %s left\n", current_.c_str(),
                     10 * tenths, duration(elapsed).c_str(), duration(total).c_str(),
                     duration(elapsed * (1.0 - f) / f).c_str());
    }
    std::fflush(stderr);
}

}  // namespace radbake
