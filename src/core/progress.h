#pragma once
// Progress of a long run: named phases with their wall time, and on a terminal a live line
// with the phase, its percentage, elapsed (phase and total) and estimated remaining time.
// Quiet (no drawing) when not shown.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace radbake {

class Progress {
public:
    // show: draw on stderr (the caller passes: stderr is a terminal and not --quiet).
    explicit Progress(bool show = false);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void beginPhase(std::string_view name);  // ends the current phase, if any
    void update(double fraction);            // 0..1 within the current phase; thread-safe, cheap
    void endPhase();

    // Prints a whole line on stderr without tearing the live progress line (which the next
    // update redraws). Use for diagnostics while progress is shown.
    void printLine(std::string_view line);

    bool shown() const { return show_; }
    // Wall seconds since construction.
    double totalSeconds() const;

    // Wall seconds of each finished phase, in order.
    const std::vector<std::pair<std::string, double>>& phaseSeconds() const { return phases_; }

private:
    void draw(bool final_line);
    bool show_;
    std::string current_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point phase_start_;
    std::atomic<double> fraction_{0.0};
    std::atomic<int64_t> last_draw_ns_{0};
    std::mutex draw_mutex_;  // one writer of the terminal line at a time
    bool line_open_ = false; // a live line is on screen without its newline
    std::vector<std::pair<std::string, double>> phases_;
};

}  // namespace radbake
