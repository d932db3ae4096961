#pragma once
// Progress of a long run: named phases with their wall time, and on a terminal a live line
// with the phase, its percentage, elapsed (phase and total) and estimated remaining time.
// Quiet (no drawing) when not shown. A host program (an asset importer's UI) gets the same
// events through a sink, and may cancel the run from it or from any thread: every phase
// polls cancelled() and the bake returns BakeStatus::Cancelled with nothing written.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace radbake {

// How a run's progress reaches stderr: not at all; as one live line redrawn on a terminal; or
// as plain lines a log keeps (each phase's end, and every 10 % of a phase past its first seconds).
enum class ProgressStyle { Hidden, Terminal, Lines };

struct ProgressEvent {
    std::string_view phase;
    double fraction = 0.0;       // 0..1 within the phase (0 while unknown)
    double phase_seconds = 0.0;  // elapsed in this phase
    double total_seconds = 0.0;  // elapsed since the run began
    bool phase_done = false;     // the phase has just ended (phase_seconds is its time)
    // The stage under way (a run of phases: the solve; empty: none), its fraction (0 while
    // unknown) and the seconds it expects to take still (valid when stage_fraction > 0).
    std::string_view stage;
    double stage_fraction = 0.0;
    double stage_seconds_left = 0.0;
};

class Progress {
public:
    // Called at each phase's start and end and at most ten times a second in between, from
    // whichever thread reported; it must be thread-safe and quick. It may call cancel().
    using Sink = std::function<void(const ProgressEvent&)>;

    // show: draw on stderr (the caller passes: stderr is a terminal and not --quiet).
    explicit Progress(bool show = false);
    explicit Progress(ProgressStyle style);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void beginPhase(std::string_view name);  // ends the current phase, if any
    void update(double fraction);            // 0..1 within the current phase; thread-safe, cheap
    void endPhase();

    // A stage: the phases begun until endStage, whose fraction and time left are reported with
    // each phase's. Its caller knows what comes after the current phase: setAhead gives the
    // seconds it expects the stage's later phases to take, as `fixed` plus `per_phase_second`
    // times the current phase's own expected length (known from its fraction as it runs).
    // Until its first setAhead a stage's fraction is unknown.
    void beginStage(std::string_view name);
    void endStage();
    void setAhead(double fixed, double per_phase_second = 0.0);

    // Prints a whole line on stderr without tearing the live progress line (which the next
    // update redraws). Use for diagnostics while progress is shown.
    void printLine(std::string_view line);

    // Whether the live terminal line is drawn.
    bool shown() const { return show_; }
    // Whether anyone sees the progress (a terminal line, log lines or a sink): work done only to
    // estimate it is skipped otherwise.
    bool watched() const { return show_ || lines_ || static_cast<bool>(sink_); }
    // The phase under way ("" between phases); read it from the thread that begins phases.
    const std::string& currentPhase() const { return current_; }

    void setSink(Sink sink) { sink_ = std::move(sink); }

    // Asks the run to stop as soon as it can; thread-safe, idempotent.
    void cancel() { cancel_.store(true); }
    bool cancelled() const { return cancel_.load(std::memory_order_relaxed); }
    // For ParallelRunner, which skips the ranges not yet started once it is set.
    const std::atomic<bool>* cancelFlag() const { return &cancel_; }
    // Wall seconds since construction.
    double totalSeconds() const;

    // Wall seconds of each finished phase, in order.
    const std::vector<std::pair<std::string, double>>& phaseSeconds() const { return phases_; }

private:
    void draw(bool final_line);
    void logLine(bool final_line);
    void notify(bool phase_done, double phase_seconds);
    struct StageEstimate {
        double fraction = 0.0, seconds_left = 0.0;
    };
    // The stage's fraction and time left now (fraction 0: not in a stage, or not known yet).
    StageEstimate stageEstimate(bool phase_done);
    std::string stageText(const StageEstimate& estimate) const;
    bool show_;
    bool lines_ = false;  // ProgressStyle::Lines
    Sink sink_;
    std::atomic<bool> cancel_{false};
    std::string current_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point phase_start_;
    std::atomic<double> fraction_{0.0};
    std::atomic<int64_t> last_draw_ns_{0};
    int logged_tenths_ = 0;  // the phase's last logged 10 % step (Lines), under draw_mutex_
    int logged_stage_tenths_ = 0;  // the stage's
    std::mutex draw_mutex_;  // one writer of the terminal line at a time
    bool line_open_ = false; // a live line is on screen without its newline
    std::vector<std::pair<std::string, double>> phases_;
    std::string stage_;
    std::chrono::steady_clock::time_point stage_start_;
    std::atomic<double> ahead_fixed_{0.0}, ahead_per_second_{0.0};
    std::atomic<double> stage_shown_{0.0};  // never falls back
    std::atomic<double> left_said_{0.0}, said_at_{0.0};  // the last time left known, and when (stage seconds)
};

}  // namespace radbake
