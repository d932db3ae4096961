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

void Progress::beginStage(std::string_view name) {
    stage_ = name;
    stage_start_ = std::chrono::steady_clock::now();
    ahead_fixed_ = -1.0;  // unknown until setAhead
    ahead_per_second_ = 0.0;
    stage_shown_ = 0.0;
    left_said_ = 0.0;
    said_at_ = 0.0;
    logged_stage_tenths_ = 0;
}

void Progress::endStage() { stage_.clear(); }

void Progress::setAhead(double fixed, double per_phase_second) {
    ahead_fixed_.store(std::max(0.0, fixed), std::memory_order_relaxed);
    ahead_per_second_.store(std::max(0.0, per_phase_second), std::memory_order_relaxed);
}

Progress::StageEstimate Progress::stageEstimate(bool phase_done) {
    if (stage_.empty() || current_.empty() || ahead_fixed_.load(std::memory_order_relaxed) < 0.0) return {};
    const double stage_elapsed = secondsSince(stage_start_);
    const double phase_elapsed = secondsSince(phase_start_);
    const double f = phase_done ? 1.0 : fraction_.load(std::memory_order_relaxed);
    double shown = stage_shown_.load(std::memory_order_relaxed);
    if (!(f > 0.01)) {
        // The phase cannot tell its length yet: the last estimate, less the time since.
        return {shown, std::max(0.0, left_said_.load(std::memory_order_relaxed) - (stage_elapsed - said_at_))};
    }
    const double phase_total = phase_elapsed / f;
    const double left = phase_total - phase_elapsed + ahead_fixed_.load(std::memory_order_relaxed) +
                        ahead_per_second_.load(std::memory_order_relaxed) * phase_total;
    const double fraction = stage_elapsed / std::max(stage_elapsed + left, 1e-9);
    while (fraction > shown && !stage_shown_.compare_exchange_weak(shown, fraction)) {
    }
    left_said_.store(left, std::memory_order_relaxed);
    said_at_.store(stage_elapsed, std::memory_order_relaxed);
    return {std::max(shown, fraction), left};
}

std::string Progress::stageText(const StageEstimate& e) const {
    if (!(e.fraction > 0.0)) return "";
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "; %s %d %%, about %s left", stage_.c_str(),
                  static_cast<int>(100.0 * e.fraction), duration(e.seconds_left).c_str());
    return buffer;
}

void Progress::notify(bool phase_done, double phase_seconds) {
    ProgressEvent event;
    event.phase = current_;
    event.fraction = phase_done ? 1.0 : fraction_.load(std::memory_order_relaxed);
    event.phase_seconds = phase_seconds;
    event.total_seconds = totalSeconds();
    event.phase_done = phase_done;
    const StageEstimate stage = stageEstimate(phase_done);
    if (!stage_.empty()) event.stage = stage_;
    event.stage_fraction = stage.fraction;
    event.stage_seconds_left = stage.seconds_left;
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
        std::fprintf(stderr, "\r\033[K%-12s %5.1f %%  elapsed %s (total %s)  remaining ~%s%s", current_.c_str(),
                     100.0 * f, duration(elapsed).c_str(), duration(total).c_str(),
                     duration(elapsed * (1.0 - f) / f).c_str(), stageText(stageEstimate(false)).c_str());
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
        std::fprintf(stderr, "radbake: %s done in %s (total %s)%s\n", current_.c_str(), duration(elapsed).c_str(),
                     duration(total).c_str(), stageText(stageEstimate(true)).c_str());
    } else {
        // A line at every 10 % of the phase, and of the stage (a long phase may hold most of it).
        const double f = fraction_.load(std::memory_order_relaxed);
        const int tenths = static_cast<int>(10.0 * f);
        const StageEstimate stage = stageEstimate(false);
        const int stage_tenths = static_cast<int>(10.0 * stage.fraction);
        const bool phase_step = tenths > logged_tenths_ && tenths < 10;
        const bool stage_step = stage_tenths > logged_stage_tenths_ && stage_tenths < 10;
        if (!phase_step && !stage_step) return;
        if (phase_step) logged_tenths_ = tenths;
        if (stage_step) logged_stage_tenths_ = stage_tenths;
        std::fprintf(stderr, "radbake: %s %d %%, %s in the phase (total %s), about %s left%s\n", current_.c_str(),
                     static_cast<int>(100.0 * f), duration(elapsed).c_str(), duration(total).c_str(),
                     duration(elapsed * (1.0 - f) / f).c_str(), stageText(stage).c_str());
    }
    std::fflush(stderr);
}

}  // namespace radbake
