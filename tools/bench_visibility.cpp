// Operations per second of the shaft machinery: shaft construction (boxes, polygons), AABB and
// OBB crossing tests, the paper's OBB occlusion test and the exact occlusion test.
//
//   bench_visibility [runs=7] [seconds_per_run=0.2]
//
// Each figure is the median over `runs` runs (min and max shown) of thread CPU time, looping
// over a fixed set of 1024 quad-to-quad configurations small enough to stay in cache: this
// measures the tests' own cost. (tools/bench_occlusion shows the cost over a large, cold set.)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "../tests/visibility/random_configs.h"
#include "visibility/occlusion.h"

using namespace radbake;
using namespace radbake::testing;

namespace {

double cpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Link {
    std::vector<DVec3> source, receiver;
    Aabb source_box, receiver_box;
    Shaft box_shaft, polygon_shaft;
    ConvexPart occluder;
};

// Quad-to-quad links with box occluders. kind 0: a random box near the link (the generator's
// mix of crossing and outside); 1: a wall box across the whole link (occludes);
// 2: a box crossing the shaft without blocking it (a column beside the link's axis).
std::vector<Link> makeLinks(int kind, size_t count, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Link> links;
    while (links.size() < count) {
        Link l;
        const DVec3 o(u(rng) * 5, u(rng) * 5, u(rng) * 5);
        const double h = 2.0 + 2.0 * std::abs(u(rng));
        const double w = 0.5 + 0.5 * std::abs(u(rng));
        l.source = rectangle(2, o.z, o.x, o.x + w, o.y, o.y + w);
        l.receiver = rectangle(2, o.z + h, o.x + 0.3 * u(rng), o.x + 0.3 * u(rng) + w,
                               o.y + 0.3 * u(rng), o.y + 0.3 * u(rng) + w);
        // Tilt the receiver a little so the polygon shaft is not a box.
        for (size_t i = 0; i < 4; ++i) l.receiver[i].z += 0.1 * (i == 2 ? 1.0 : 0.0) * u(rng);
        l.receiver[3].z = l.receiver[0].z + l.receiver[2].z - l.receiver[1].z;  // keep planar
        const DVec3 mid = 0.25 * (l.source[0] + l.source[2] + l.receiver[0] + l.receiver[2]);
        const double a = 0.3 * u(rng);
        const std::array<DVec3, 3> axes = {DVec3(std::cos(a), std::sin(a), 0),
                                           DVec3(-std::sin(a), std::cos(a), 0), DVec3(0, 0, 1)};
        if (kind == 0) {
            l.occluder = orientedBoxPart(mid + DVec3(u(rng), u(rng), u(rng) * 0.5 * h), axes,
                                         DVec3(0.1 + std::abs(u(rng)), 0.1 + std::abs(u(rng)),
                                               0.05 + 0.3 * std::abs(u(rng))));
        } else if (kind == 1) {
            l.occluder = orientedBoxPart(mid, axes, DVec3(3.0, 3.0, 0.05 + 0.1 * std::abs(u(rng))));
        } else {
            l.occluder = orientedBoxPart(mid + DVec3(0.45 * w, 0, 0), axes,
                                         DVec3(0.1 * w, 0.1 * w, 0.3 * h));
        }
        l.source_box = boxOfPoints(l.source);
        l.receiver_box = boxOfPoints(l.receiver);
        l.box_shaft = shaftBetweenBoxes(l.source_box, l.receiver_box);
        l.polygon_shaft = shaftBetweenPolygons(l.source, l.receiver);
        if (kind == 1 && !occludesExact(l.source, l.receiver, l.occluder)) continue;
        if (kind == 2 && (occludesExact(l.source, l.receiver, l.occluder) ||
                          classifyObb(l.polygon_shaft, l.occluder.obb) == Side::Outside)) {
            continue;
        }
        links.push_back(std::move(l));
    }
    return links;
}

size_t g_sink = 0;

void measure(const std::string& name, const std::vector<Link>& links, int runs,
             double seconds_per_run, const std::function<size_t(const Link&)>& op) {
    std::vector<double> rates;
    for (int r = 0; r < runs; ++r) {
        size_t ops = 0;
        const double start = cpuSeconds();
        double now = start;
        while (now - start < seconds_per_run) {
            for (const Link& l : links) g_sink += op(l);
            ops += links.size();
            now = cpuSeconds();
        }
        rates.push_back(static_cast<double>(ops) / (now - start));
    }
    std::sort(rates.begin(), rates.end());
    std::printf("%-44s %12.3g ops/s  (%6.1f ns; min %.3g, max %.3g)\n", name.c_str(),
                rates[rates.size() / 2], 1e9 / rates[rates.size() / 2], rates.front(),
                rates.back());
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::atoi(argv[1]) : 7;
    const double seconds_per_run = argc > 2 ? std::atof(argv[2]) : 0.2;
    const auto random_links = makeLinks(0, 1024, 11);
    const auto wall_links = makeLinks(1, 1024, 12);
    const auto column_links = makeLinks(2, 1024, 13);
    std::printf("median of %d runs of %.2f s CPU each, 1024 quad-to-quad links per set\n", runs,
                seconds_per_run);

    measure("shaft between boxes (Haines-Wallace)", random_links, runs, seconds_per_run,
            [](const Link& l) { return shaftBetweenBoxes(l.source_box, l.receiver_box).planes.size(); });
    measure("shaft between polygons (quad hull)", random_links, runs, seconds_per_run,
            [](const Link& l) { return shaftBetweenPolygons(l.source, l.receiver).planes.size(); });
    measure("AABB crossing test (polygon shaft)", random_links, runs, seconds_per_run,
            [](const Link& l) {
                return size_t(classifyAabb(l.polygon_shaft, l.occluder.aabb) == Side::Crossing);
            });
    measure("OBB crossing test (polygon shaft)", random_links, runs, seconds_per_run,
            [](const Link& l) {
                return size_t(classifyObb(l.polygon_shaft, l.occluder.obb) == Side::Crossing);
            });
    measure("OBB crossing + paper's OBB occlusion test", random_links, runs, seconds_per_run,
            [](const Link& l) { return size_t(occludesObb(l.box_shaft, l.occluder.obb)); });
    measure("paper's OBB occlusion test, wall boxes", wall_links, runs, seconds_per_run,
            [](const Link& l) { return size_t(occludesObb(l.box_shaft, l.occluder.obb)); });
    measure("exact test, random boxes near the link", random_links, runs, seconds_per_run,
            [](const Link& l) { return size_t(occludesExact(l.source, l.receiver, l.occluder)); });
    measure("exact test, wall boxes (occluding)", wall_links, runs, seconds_per_run,
            [](const Link& l) { return size_t(occludesExact(l.source, l.receiver, l.occluder)); });
    measure("exact test, columns crossing (not occluding)", column_links, runs, seconds_per_run,
            [](const Link& l) { return size_t(occludesExact(l.source, l.receiver, l.occluder)); });
    std::printf("(checksum %zu)\n", g_sink);
    return 0;
}
