// Occlusion tests against a brute-force segment test on random configurations (>= 10^6 by
// default): false occlusions, missed occlusions and time per test for each mode.
//
//   bench_occlusion [configurations=1000000] [subdivisions=2] [seed=1]
//
// Modes: aabb = the paper's AABB column (culling only, never occludes), obb = the paper's
// OBB test (on the Haines-Wallace box shaft), exact = the conservative test. Ground truth: a
// grid of sample points on each polygon (vertices + a barycentric grid of `subdivisions`
// steps per fan triangle), every source point joined to every receiver point, each segment
// tested exactly against the occluder. "real occlusion" = every sampled segment passes
// through the occluder's interior (necessary for a true occlusion, not sufficient, so
// "missed" can only be overestimated by a coarse grid, and "false" underestimated).
// The random configurations come from tests/visibility/random_configs.h (shared with the
// property test).
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "../tests/visibility/random_configs.h"
#include "visibility/occlusion.h"
#include "visibility/reference.h"

using namespace radbake;
using namespace radbake::testing;

namespace {

// Thread CPU time, not wall time: the machine is shared, and a preempted thread should not
// be charged for the time it did not run.
struct Clock {
    using time_point = double;
    static double now() {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
    }
};

double seconds(double a, double b) { return b - a; }

struct Prepared {
    Configuration config;
    Shaft box_shaft;
    Shaft polygon_shaft;
};

}  // namespace

int main(int argc, char** argv) {
    const long total = argc > 1 ? std::atol(argv[1]) : 1000000;
    const int subdivisions = argc > 2 ? std::atoi(argv[2]) : 2;
    const uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
    ConfigurationGenerator generator(seed);

    constexpr long kBatch = 10000;
    long done = 0;
    size_t real = 0, touched = 0;
    size_t obb_claims = 0, obb_false = 0, obb_missed = 0;
    size_t exact_claims = 0, exact_false = 0, exact_missed = 0;
    size_t aabb_false_outside = 0, obb_false_outside = 0;
    double t_aabb = 0, t_obb_cross = 0, t_obb = 0, t_exact = 0;
    size_t sink = 0;  // keeps the timed calls alive
    std::vector<Prepared> batch;
    std::vector<char> obb_result, exact_result;
    while (done < total) {
        const long n = std::min(kBatch, total - done);
        batch.clear();
        for (long i = 0; i < n; ++i) {
            Prepared p;
            p.config = generator.next();
            p.box_shaft = shaftBetweenBoxes(boxOfPoints(p.config.source),
                                            boxOfPoints(p.config.receiver));
            p.polygon_shaft = shaftBetweenPolygons(p.config.source, p.config.receiver);
            batch.push_back(std::move(p));
        }
        obb_result.assign(n, 0);
        exact_result.assign(n, 0);
        auto t0 = Clock::now();
        for (const Prepared& p : batch) {
            sink += classifyAabb(p.box_shaft, p.config.occluder.aabb) == Side::Crossing;
        }
        auto t1 = Clock::now();
        for (const Prepared& p : batch) {
            sink += classifyObb(p.box_shaft, p.config.occluder.obb) == Side::Crossing;
        }
        auto t2 = Clock::now();
        for (long i = 0; i < n; ++i) {
            obb_result[i] = occludesObb(batch[i].box_shaft, batch[i].config.occluder.obb);
        }
        auto t3 = Clock::now();
        for (long i = 0; i < n; ++i) {
            const Configuration& c = batch[i].config;
            exact_result[i] = occludesExact(c.source, c.receiver, c.occluder);
        }
        auto t4 = Clock::now();
        t_aabb += seconds(t0, t1);
        t_obb_cross += seconds(t1, t2);
        t_obb += seconds(t2, t3);
        t_exact += seconds(t3, t4);

        for (long i = 0; i < n; ++i) {
            const Prepared& p = batch[i];
            const Configuration& c = p.config;
            const auto ps = polygonSamplePoints(c.source, subdivisions);
            const auto pr = polygonSamplePoints(c.receiver, subdivisions);
            const SegmentCount count = countSegmentHits(ps, pr, c.occluder);
            const bool all_hit = count.hits_strict == count.segments;
            real += all_hit;
            if (count.hits_any > 0) {
                ++touched;
                for (const Shaft* shaft : {&p.box_shaft, &p.polygon_shaft}) {
                    aabb_false_outside += classifyAabb(*shaft, c.occluder.aabb) == Side::Outside;
                    obb_false_outside += classifyObb(*shaft, c.occluder.obb) == Side::Outside;
                }
            }
            obb_claims += obb_result[i];
            obb_false += obb_result[i] && !all_hit;
            obb_missed += !obb_result[i] && all_hit;
            exact_claims += exact_result[i];
            exact_false += exact_result[i] && !all_hit;
            exact_missed += !exact_result[i] && all_hit;
        }
        done += n;
    }
    const double per = 1e9 / static_cast<double>(done);
    std::printf("configurations        %ld (seed %llu, grid subdivisions %d)\n", done,
                static_cast<unsigned long long>(seed), subdivisions);
    std::printf("real occlusions       %zu (every sampled segment hits)\n", real);
    std::printf("touched by a segment  %zu\n", touched);
    std::printf("false outside         aabb %zu, obb %zu (over both shaft kinds)\n",
                aabb_false_outside, obb_false_outside);
    std::printf("%-6s %10s %10s %10s %14s\n", "mode", "claims", "false", "missed", "cpu ns/test");
    std::printf("%-6s %10d %10d %10zu %14.1f  (AABB crossing test)\n", "aabb", 0, 0, real,
                t_aabb * per);
    std::printf("%-6s %10s %10s %10s %14.1f  (OBB crossing test)\n", "", "", "", "",
                t_obb_cross * per);
    std::printf("%-6s %10zu %10zu %10zu %14.1f  (OBB crossing + paper's test)\n", "obb",
                obb_claims, obb_false, obb_missed, t_obb * per);
    std::printf("%-6s %10zu %10zu %10zu %14.1f\n", "exact", exact_claims, exact_false,
                exact_missed, t_exact * per);
    return sink == 0 ? 1 : 0;
}
