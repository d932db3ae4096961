#pragma once
// Random source / receiver / occluder configurations for the occlusion property test and
// tools/bench_occlusion.cpp (deterministic: a seeded std::mt19937_64).
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/types.h"
#include "part_builders.h"

namespace radbake::testing {

enum class OccluderKind { AxisBox, RotatedBox, ThinPlate, TiltedPolygon, Touching, Count };

struct Configuration {
    std::vector<DVec3> source;
    std::vector<DVec3> receiver;
    ConvexPart occluder;
    OccluderKind kind = OccluderKind::AxisBox;
};

class ConfigurationGenerator {
public:
    explicit ConfigurationGenerator(uint64_t seed) : rng_(seed) {}

    Configuration next() {
        Configuration c;
        c.kind = static_cast<OccluderKind>(index_++ % static_cast<int>(OccluderKind::Count));
        if (c.kind == OccluderKind::Touching) return touching();
        const double size_s = uniform(0.2, 2.0), size_r = uniform(0.2, 2.0);
        const DVec3 origin = randomVector(5.0);
        const DVec3 link = randomUnit() * uniform(1.0, 8.0);
        c.source = randomPolygon(origin, size_s, tiltedNormal(link, 1.2));
        c.receiver = randomPolygon(origin + link, size_r, tiltedNormal(-link, 1.2));
        const double t = uniform(-0.2, 1.2);
        const DVec3 at = origin + t * link + randomVector(0.3 * (size_s + size_r));
        const double size = uniform(0.3, 3.0) * std::max(size_s, size_r);
        const DVec3 dir = glm::normalize(link);
        switch (c.kind) {
        case OccluderKind::AxisBox: {
            DVec3 half(uniform(0.05, 1.0) * size, uniform(0.05, 1.0) * size,
                       uniform(0.05, 1.0) * size);
            c.occluder = orientedBoxPart(at, {DVec3(1, 0, 0), DVec3(0, 1, 0), DVec3(0, 0, 1)},
                                         half);
            break;
        }
        case OccluderKind::RotatedBox:
            c.occluder = orientedBoxPart(at, randomFrame(randomUnit()),
                                         DVec3(uniform(0.05, 1.0) * size,
                                               uniform(0.05, 1.0) * size,
                                               uniform(0.05, 1.0) * size));
            break;
        case OccluderKind::ThinPlate: {
            const double thickness = std::pow(10.0, uniform(-9.0, -1.0)) * size;
            auto frame = randomFrame(tiltedNormal(dir, 0.6));
            c.occluder = orientedBoxPart(at, frame, DVec3(size, uniform(0.3, 1.0) * size,
                                                          thickness));
            break;
        }
        case OccluderKind::TiltedPolygon:
        default:
            c.occluder = flatPart(randomPolygon(at, size, tiltedNormal(dir, 0.8)));
            break;
        }
        return c;
    }

private:
    double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
    DVec3 randomVector(double r) { return DVec3(uniform(-r, r), uniform(-r, r), uniform(-r, r)); }
    DVec3 randomUnit() {
        for (;;) {
            const DVec3 v = randomVector(1.0);
            const double l = glm::length(v);
            if (l > 0.1 && l <= 1.0) return v / l;
        }
    }
    // A unit vector within about `spread` radians of `axis`.
    DVec3 tiltedNormal(const DVec3& axis, double spread) {
        const DVec3 n = glm::normalize(axis) + randomVector(std::tan(spread) * 0.8);
        return glm::normalize(n);
    }
    std::array<DVec3, 3> randomFrame(const DVec3& normal) {
        DVec3 helper = std::abs(normal.x) < 0.9 ? DVec3(1, 0, 0) : DVec3(0, 1, 0);
        const double angle = uniform(0.0, 2.0 * kPi);
        DVec3 u = glm::normalize(glm::cross(normal, helper));
        DVec3 v = glm::cross(normal, u);
        const DVec3 ru = std::cos(angle) * u + std::sin(angle) * v;
        return {ru, glm::cross(normal, ru), normal};
    }
    // Convex polygon: 3 to 6 points on an ellipse at sorted random angles.
    std::vector<DVec3> randomPolygon(const DVec3& center, double size, const DVec3& normal) {
        const auto frame = randomFrame(normal);
        const int n = 3 + static_cast<int>(uniform(0.0, 4.0));
        const double ru = size * uniform(0.3, 1.0), rv = size * uniform(0.05, 1.0);
        std::vector<double> angles(n);
        for (int i = 0; i < n; ++i) angles[i] = (i + uniform(0.1, 0.9)) * 2.0 * kPi / n;
        std::vector<DVec3> loop;
        for (double a : angles) {
            loop.push_back(center + frame[0] * (ru * std::cos(a)) + frame[1] * (rv * std::sin(a)));
        }
        return loop;
    }
    // Near-degenerate and touching cases on an axis-aligned layout: source on z = 0,
    // receiver on z = h; a wall whose faces or edges lie exactly on the shaft's boundary,
    // the source or the receiver, or a hair (1e-12 .. 1e-6) away.
    Configuration touching() {
        Configuration c;
        c.kind = OccluderKind::Touching;
        const double h = uniform(0.5, 3.0);
        c.source = rectangle(2, 0.0, 0.0, 1.0, 0.0, 1.0);
        c.receiver = rectangle(2, h, 0.0, 1.0, 0.0, 1.0);
        const double hair = uniform(0.0, 1.0) < 0.5 ? 0.0 : std::pow(10.0, uniform(-12.0, -6.0)) *
                                                              (uniform(0.0, 1.0) < 0.5 ? -1 : 1);
        const int variant = static_cast<int>(uniform(0.0, 5.0));
        const double z = uniform(0.1, 0.9) * h;
        switch (variant) {
        case 0:  // wall beside the shaft, touching its side x = 1
            c.occluder = boxPart(DVec3(1.0 + hair, -1, z - 0.1), DVec3(2.0, 2.0, z + 0.1));
            break;
        case 1:  // wall just under the source (touching it from behind)
            c.occluder = boxPart(DVec3(-1, -1, -0.5), DVec3(2, 2, hair));
            break;
        case 2:  // wall exactly covering the cross-section, edges on the shaft's sides
            c.occluder = boxPart(DVec3(0.0 - hair, 0.0 - hair, z - 0.01),
                                 DVec3(1.0 + hair, 1.0 + hair, z + 0.01));
            break;
        case 3:  // plate in the plane of the receiver, the receiver lying on it
            c.occluder = flatPart(rectangle(2, h + hair, -1.0, 2.0, -1.0, 2.0));
            break;
        default:  // box touching the shaft along an edge only: corner column at x = y = 1
            c.occluder = boxPart(DVec3(1.0 + hair, 1.0 + hair, 0.2 * h), DVec3(2, 2, 0.8 * h));
            break;
        }
        return c;
    }

    std::mt19937_64 rng_;
    int index_ = 0;
};

}  // namespace radbake::testing
