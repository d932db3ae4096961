#pragma once
// The cluster refinement's progress (ClusterRefiner::refine, cluster.cpp). Its levels differ in
// cost per link by up to 10 x (long candidate lists near the top) and in links by 100 x, so
// neither their count nor a prior on their shape tells the time to come (docs/scale.md, "The
// solve's progress"): once a level holds kSampleFrom links, every stride-th of them is refined
// ahead to the end (results discarded; at most 1/kSampleStride more work), and each level to
// come is expected to take what its sample took times the stride, scaled by how the last
// levels done compared with theirs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace radbake {

inline constexpr size_t kSampleFrom = 16384;
inline constexpr size_t kSampleStride = 128;
inline constexpr size_t kSampleLinks = 16384;  // links sampled from a larger level
inline constexpr size_t kScaleLevels = 4;
// A root link refined after the clusters (refine.cpp) costs about this share of the mean
// cluster link's evaluation.
inline constexpr double kRootLinkCost = 0.5;

inline double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

class RefinementClock {
public:
    struct Sample {
        std::vector<double> level_seconds;  // per level from the sampled one, times the stride
        double evaluations = 0.0;           // cluster links evaluated, times the stride
        double root_links = 0.0;            // root links made, times the stride
    };
    bool sampled() const { return sampled_; }
    void setSample(Sample sample, size_t root_links) {
        sampled_ = true;
        sample_ = std::move(sample);
        root_links_expected_ = static_cast<double>(root_links) + sample_.root_links;
        double seconds = 0.0;
        for (double t : sample_.level_seconds) seconds += t;
        root_link_seconds_ = kRootLinkCost * seconds / std::max(sample_.evaluations, 1.0);
    }
    void beginLevel() { level_start_ = std::chrono::steady_clock::now(); }
    void endLevel() {
        if (!sampled_) return;
        if (sampled_level_ < sample_.level_seconds.size()) {
            done_real_.push_back(secondsSince(level_start_));
            done_expected_.push_back(sample_.level_seconds[sampled_level_]);
        }
        ++sampled_level_;
    }
    // The phase's fraction `level_done` into the current level, with `root_links` made so far
    // (the phase refines them next); never below what it said before.
    double fraction(double level_done, size_t root_links) {
        if (!sampled_) return show(0.0);  // the first levels are cheap; a guess would overshoot
        // The sample's total is close, but its levels are not each: the full top levels run
        // faster (neighbouring links share their lists), the deep ones slower, and the machine's
        // speed drifts. The last few levels' ratio to their sample scales the rest, damped.
        double real = 0.0, expected = 0.0;
        const size_t from = done_real_.size() > kScaleLevels ? done_real_.size() - kScaleLevels : 0;
        for (size_t k = from; k < done_real_.size(); ++k) real += done_real_[k], expected += done_expected_[k];
        const double scale = expected > 0.0 ? std::sqrt(std::clamp(real / expected, 0.25, 4.0)) : 1.0;
        double left = 0.0;
        for (size_t k = sampled_level_; k < sample_.level_seconds.size(); ++k)
            left += sample_.level_seconds[k] * (k == sampled_level_ ? 1.0 - level_done : 1.0);
        left += std::max(root_links_expected_, static_cast<double>(root_links)) * root_link_seconds_;
        const double elapsed = secondsSince(start_);
        return show(elapsed / std::max(elapsed + scale * left, 1e-9));
    }
    // The cluster links' share of the phase once they are done.
    double finished(size_t root_links) {
        if (!sampled_) return show(0.5);
        const double elapsed = secondsSince(start_);
        return show(elapsed / std::max(elapsed + static_cast<double>(root_links) * root_link_seconds_, 1e-9));
    }

private:
    double show(double f) { return shown_ = std::max(shown_, std::min(f, 1.0)); }
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), level_start_ = start_;
    bool sampled_ = false;
    Sample sample_;
    size_t sampled_level_ = 0;
    double root_links_expected_ = 0.0, root_link_seconds_ = 0.0;
    std::vector<double> done_real_, done_expected_;  // per level since the sample
    double shown_ = 0.0;
};

}  // namespace radbake
