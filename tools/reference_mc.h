#pragma once
// A brute-force Monte Carlo reference for probe irradiance, independent of the radiosity
// hierarchy, the shafts and Embree: its own median-split BVH over the scene's triangles and
// an exact double-precision ray/triangle test. Header-only so that tools/reference_mc.cpp and
// tests/harness/ compile the same code (every tools/*.cpp is its own executable).
//
// Two unbiased estimators (per probe x with normal n, per channel).
//
// Path tracing with next-event estimation and multiple importance sampling (the default,
// McOptions::next_event): at every path vertex x_k (the probe, then each hit) sample one point
// y on the emitters (triangle chosen with probability proportional to area x max channel of
// L_e, uniform on it) and add throughput * L_e(y) cos_x cos_y / r^2 / pdf_area(y) when y's
// front faces x_k and the segment is clear; then continue as below, where a path that HITS an
// emitter adds its pi L_e too. Each of the two contributions is weighted by the balance
// heuristic (Veach): w = p / (p_light + p_cosine), both densities per solid angle, so the sum
// stays unbiased, small lights are found by light sampling and large near ones (a furnace's
// walls, where 1/r^2 makes light sampling noisy) by the cosine samples.
//
// Pure path tracing (next_event = false): draw a cosine-weighted direction,
// follow the path; at every hit y_k on a FRONT face add pi * L_e(y_k) times the throughput,
// then continue with probability q = max channel of rho(y_k) (Russian roulette), the
// throughput multiplied by rho / q. With pdf cos/pi, pi * L(omega) is an unbiased estimate
// of H = integral of L cos d omega, and L(y) = L_e(y) + rho(y) H(y) / pi recurses into the
// same estimate, so a path gives sum_k pi L_e(y_k) prod_{i<k} rho_i, unbiased with no depth
// cut. Back faces are black and absorb (patches are one-sided, as in the solver), except on
// two-sided meshes (Mesh::solid false, scene/two_sided.h), which reflect and emit alike on both
// sides: a hit from behind sees the face with its normal flipped. Back twins (Mesh::back) are
// skipped, their front stands for both sides. The background is black, or the sky (below).
// A transmitting surface (meshTransmittance t > 0, a thin pane) lets a path through with
// probability t, keeping its direction, and a shadow segment keeps t of its light; met, it
// reflects as any surface does, so it reflects rho (1 - t) of what arrives. Per-face/per-vertex
// colours and textures are ignored (material rho only).
//
// Punctual lights (VRML PointLight, SpotLight, DirectionalLight; Scene::lights), in both
// estimators: at every path vertex x_k, each light's irradiance H_l(x_k) on the side x_k's
// normal faces, with one shadow segment, is added times the throughput (so a bounce vertex
// adds its rho times H_l, as the emitter samples do). A delta light cannot be hit by a path, so
// this is its only estimator and needs no MIS weight. Their meaning is radbake's
// (src/radiosity/punctual_lights.h), implemented here on its own: Point and Spot
// H = I cos / d^2 / max(a0 + a1 d + a2 d^2, 1), none beyond `radius`, a spot's factor linear
// in the angle from its beam width to its cut-off; Directional H = E cos. A scoped light lights
// only the meshes of its scope directly; probes (no mesh) are lit by every light. A directional
// light with an angular diameter (the sun of --sun) is a disc of half-angle a at infinity with
// radiance E / (pi sin^2 a), sampled uniformly over its cone: H = E 2 / (1 + cos a) cos V.
//
// The sky (Scene::sky, scene/daylight.h): a path whose cosine-sampled ray leaves the scene adds
// pi L_sky(direction) times the throughput (L_sky 0 at and below the horizon; the uniform sky's
// radiance, or the CIE overcast sky's Lz (1 + 2 cos theta) / 3 above it; a VRML97 Background's
// colour ramps over the whole sphere; an environment map's texel), implemented here on its own. Unbiased, not light-sampled: a sky seen through a small window needs many paths.
//
// Determinism: the random stream of probe i depends only on (seed, i), so results are
// identical for any thread count.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <thread>
#include <vector>

#include "core/math.h"
#include "scene/scene.h"

namespace radbake::reference {

struct McTriangle {
    DVec3 v0{0.0}, e1{0.0}, e2{0.0};
    DVec3 normal{0.0};  // unit, counter-clockwise side = front
    DVec3 reflectance{0.0};
    DVec3 emission{0.0};  // radiance L_e
    bool two_sided = false;  // both faces reflect and emit
    double transmittance = 0.0;  // the share of light that passes through it (meshTransmittance)
    uint32_t mesh = 0;       // index into Scene::meshes (a scoped light lights only some meshes)
};

// The normal of the face of `tri` that a ray along `dir` meets, and the cosine there (> 0),
// or a cosine <= 0 when it meets a one-sided triangle's back.
inline std::pair<DVec3, double> faceMet(const McTriangle& tri, const DVec3& dir) {
    const double cos_y = -glm::dot(dir, tri.normal);
    if (cos_y < 0.0 && tri.two_sided) return {-tri.normal, -cos_y};
    return {tri.normal, cos_y};
}

struct McHit {
    double t = 0.0;
    uint32_t triangle = 0;
};

// A punctual light as the reference reads it. The meaning is the one
// src/radiosity/punctual_lights.h documents; this is a separate implementation of it, so that
// a slip in either shows as a disagreement.
struct McLight {
    LightType type = LightType::Point;
    DVec3 position{0.0};
    DVec3 axis{0.0, 0.0, -1.0};  // unit: where a spot points, where directional light travels
    DVec3 strength{0.0};         // point and spot: radiant intensity I, W/sr; directional: E, W/m^2
    DVec3 attenuation{1.0, 0.0, 0.0};
    double radius = 0.0;
    double beam_width = 0.0, cut_off_angle = 0.0;
    double cone_cos = 1.0;       // directional: cos of the disc's half-angle (1: a point at infinity)
    bool scoped = false;
    std::vector<uint32_t> scope;  // sorted indices into Scene::meshes, when scoped
};

// The sky as the reference reads it (its own copy of scene/daylight.h's meaning).
struct McSky {
    SkyModel model = SkyModel::None;
    DVec3 radiance{0.0};
    DVec3 up{0.0, 1.0, 0.0};
    BackgroundSky background;
    std::shared_ptr<const EnvironmentMap> map;

    // The map's texel holding `direction`: the top row at the zenith, the centre column at azimuth 0
    // (the first axis after up's, x for y up), azimuth growing to the right towards the next axis
    // (negated for a negative up).
    DVec3 mapTexel(const DVec3& direction) const {
        const int axis = std::abs(up.x) > 0.5 ? 0 : std::abs(up.y) > 0.5 ? 1 : 2;
        const int east = axis == 0 ? 1 : 0, north = axis == 2 ? 1 : 2;
        const double sign = up[axis] < 0.0 ? -1.0 : 1.0;
        const DVec3 d = glm::normalize(direction);
        const double elevation = std::asin(std::clamp(d[axis] * sign, -1.0, 1.0));
        const double azimuth = std::atan2(d[north] * sign, d[east]);
        const int x = std::clamp(int((azimuth / (2.0 * kPi) + 0.5) * map->width), 0, map->width - 1);
        const int y = std::clamp(int((0.5 - elevation / kPi) * map->height), 0, map->height - 1);
        const float* texel = &map->rgb[(size_t(y) * map->width + x) * 3];
        return DVec3(texel[0], texel[1], texel[2]);
    }

    // A Background's ramp: colour k at angle a_k (a_0 = 0, a_k = angles[k - 1]), linear between.
    static DVec3 ramp(const std::vector<float>& angles, const std::vector<Vec3>& colours, double angle) {
        if (colours.empty()) return DVec3(0.0);
        const size_t n = std::min(colours.size(), angles.size() + 1);
        for (size_t k = 1; k < n; ++k) {
            const double a0 = k == 1 ? 0.0 : angles[k - 2], a1 = angles[k - 1];
            if (angle < a1) {
                const double w = a1 > a0 ? std::max(0.0, angle - a0) / (a1 - a0) : 1.0;
                return DVec3(colours[k - 1]) * (1.0 - w) + DVec3(colours[k]) * w;
            }
        }
        return DVec3(colours[n - 1]);
    }

    DVec3 arriving(const DVec3& direction) const {
        const double c = glm::dot(direction, up) / glm::length(up);
        if (model == SkyModel::Map) return map ? radiance * mapTexel(direction) : DVec3(0.0);
        if (model == SkyModel::Background) {
            const double zenith = std::acos(std::clamp(c, -1.0, 1.0)), nadir = kPi - zenith;
            const auto& b = background;
            if (!b.ground_color.empty() && !b.ground_angle.empty() && nadir <= b.ground_angle.back())
                return radiance * ramp(b.ground_angle, b.ground_color, nadir);
            return radiance * ramp(b.sky_angle, b.sky_color, zenith);
        }
        if (model == SkyModel::None || !(c > 0.0)) return DVec3(0.0);
        return model == SkyModel::Overcast ? radiance * ((1.0 + 2.0 * c) / 3.0) : radiance;
    }
};

// The lights that shine: those switched off, black, or without a direction are left out.
inline std::vector<McLight> readLights(const Scene& scene) {
    std::vector<McLight> lights;
    for (const Light& light : scene.lights) {
        McLight mc;
        mc.strength = glm::max(DVec3(light.color), DVec3(0.0)) * std::max(0.0, double(light.intensity));
        const double axis_length = glm::length(DVec3(light.direction));
        const bool aimed = light.type == LightType::Point || (axis_length > 0.0 && std::isfinite(axis_length));
        if (!light.on || !aimed || !(std::max(mc.strength.x, std::max(mc.strength.y, mc.strength.z)) > 0.0)) continue;
        mc.type = light.type;
        mc.position = DVec3(light.position);
        if (light.type != LightType::Point) mc.axis = DVec3(light.direction) / axis_length;
        mc.attenuation = DVec3(light.attenuation);
        mc.radius = light.radius;
        mc.beam_width = light.beam_width;
        mc.cut_off_angle = light.cut_off_angle;
        if (light.type == LightType::Directional && light.angular_diameter > 0.0f)
            mc.cone_cos = std::cos(0.5 * std::min(double(light.angular_diameter), 0.99 * kPi));
        mc.scoped = light.scoped;
        mc.scope = light.scope;
        lights.push_back(std::move(mc));
    }
    return lights;
}

// The scene as the reference sees it: its triangles in a median-split BVH (centroid median on
// the longest axis, <= 4 triangles a leaf; simple rather than SAH-optimal: the reference is run
// offline on scenes of up to ~1e5 triangles), and its punctual lights.
class McBvh {
public:
    explicit McBvh(const Scene& scene) {
        for (uint32_t mesh_index = 0; mesh_index < scene.meshes.size(); ++mesh_index) {
            const Mesh& mesh = scene.meshes[mesh_index];
            if (mesh.back) continue;  // its front is two-sided
            const Material* material = mesh.material < scene.materials.size() ? &scene.materials[mesh.material] : nullptr;
            for (const UVec3& tri : mesh.triangles) {
                if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() || tri.z >= mesh.positions.size())
                    continue;
                const DVec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
                const DVec3 cross = glm::cross(b - a, c - a);
                const double length = glm::length(cross);
                if (!(length > 0.0) || !std::isfinite(length)) continue;  // degenerate: no area, no light
                McTriangle t;
                t.v0 = a;
                t.e1 = b - a;
                t.e2 = c - a;
                t.normal = cross / length;
                t.two_sided = !mesh.solid;
                t.transmittance = meshTransmittance(scene, mesh);
                t.mesh = mesh_index;
                if (material) {
                    t.reflectance = DVec3(material->reflectance);
                    t.emission = DVec3(material->emission);
                }
                triangles_.push_back(t);
            }
        }
        DVec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (const McTriangle& t : triangles_) {
            for (const DVec3& p : {t.v0, t.v0 + t.e1, t.v0 + t.e2}) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
        }
        extent_ = triangles_.empty() ? 0.0 : glm::length(hi - lo);
        lights_ = readLights(scene);
        sky_ = McSky{scene.sky.model, DVec3(scene.sky.radiance), DVec3(scene.sky.up), scene.sky.background,
                     scene.sky.map};
        order_.resize(triangles_.size());
        for (uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
        if (!triangles_.empty()) build(0, static_cast<uint32_t>(order_.size()));
    }

    const std::vector<McTriangle>& triangles() const { return triangles_; }
    const std::vector<McLight>& lights() const { return lights_; }
    const McSky& sky() const { return sky_; }
    bool lit() const { return !lights_.empty() || sky_.model != SkyModel::None; }
    double extent() const { return extent_; }
    // How far a path's origin is pushed off the surface it leaves, along that surface's
    // normal: 1e-6 x the scene's diagonal, 16x the float rounding of stored vertices (~6e-8
    // relative to coordinates of the order of the extent), yet small enough that the light
    // leaking past a corner through the offset is below 1e-5 of any probe's value.
    double epsilon() const { return 1e-6 * extent_; }

    // Closest hit with t in (t_min, t_max); skips triangle `skip` (the one the ray leaves).
    bool closestHit(const DVec3& origin, const DVec3& dir, double t_min, double t_max, uint32_t skip,
                    McHit& hit) const {
        if (nodes_.empty()) return false;
        const DVec3 inv(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z);
        bool found = false;
        double best = t_max;
        std::array<uint32_t, 128> stack;
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes_[stack[--top]];
            if (!slab(node, origin, inv, t_min, best)) continue;
            if (node.count > 0) {
                for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                    const uint32_t index = order_[k];
                    if (index == skip) continue;
                    double t;
                    if (intersect(triangles_[index], origin, dir, t) && t > t_min && t < best) {
                        best = t;
                        hit.t = t;
                        hit.triangle = index;
                        found = true;
                    }
                }
            } else {
                // Visit the nearer child first (pushed last).
                const Node& left = nodes_[node.first];
                const Node& right = nodes_[node.first + 1];
                const double dl = glm::dot((left.lo + left.hi) * 0.5 - origin, dir);
                const double dr = glm::dot((right.lo + right.hi) * 0.5 - origin, dir);
                if (top + 2 > static_cast<int>(stack.size())) return found;  // cannot happen at depth < 64
                if (dl < dr) {
                    stack[top++] = node.first + 1;
                    stack[top++] = node.first;
                } else {
                    stack[top++] = node.first;
                    stack[top++] = node.first + 1;
                }
            }
        }
        return found;
    }

private:
    struct Node {
        DVec3 lo{0.0}, hi{0.0};
        uint32_t first = 0;  // leaf: first index into order_; inner: index of the left child
        uint32_t count = 0;  // 0 for inner nodes
    };

    static bool intersect(const McTriangle& tri, const DVec3& origin, const DVec3& dir, double& t) {
        // Moller-Trumbore in double; edges count as inside (closed triangles), so a ray through
        // a shared edge cannot slip between two triangles.
        const DVec3 p = glm::cross(dir, tri.e2);
        const double det = glm::dot(tri.e1, p);
        if (det == 0.0) return false;
        const double inv_det = 1.0 / det;
        const DVec3 s = origin - tri.v0;
        const double u = glm::dot(s, p) * inv_det;
        if (u < 0.0 || u > 1.0) return false;
        const DVec3 q = glm::cross(s, tri.e1);
        const double v = glm::dot(dir, q) * inv_det;
        if (v < 0.0 || u + v > 1.0) return false;
        t = glm::dot(tri.e2, q) * inv_det;
        return true;
    }

    static bool slab(const Node& node, const DVec3& origin, const DVec3& inv, double t_min, double t_max) {
        double t0 = t_min, t1 = t_max;
        for (int axis = 0; axis < 3; ++axis) {
            double a = (node.lo[axis] - origin[axis]) * inv[axis];
            double b = (node.hi[axis] - origin[axis]) * inv[axis];
            if (a > b) std::swap(a, b);
            // NaN (0 * inf on a slab face) must not reject: treat as the whole line.
            if (!(a != a)) t0 = std::max(t0, a);
            if (!(b != b)) t1 = std::min(t1, b);
            if (t0 > t1) return false;
        }
        return true;
    }

    uint32_t build(uint32_t first, uint32_t count) {
        const uint32_t index = static_cast<uint32_t>(nodes_.size());
        nodes_.push_back({});
        DVec3 lo(std::numeric_limits<double>::max()), hi(-lo), clo = lo, chi = hi;
        for (uint32_t k = first; k < first + count; ++k) {
            const McTriangle& t = triangles_[order_[k]];
            const DVec3 b = t.v0 + t.e1, c = t.v0 + t.e2;
            lo = glm::min(lo, glm::min(t.v0, glm::min(b, c)));
            hi = glm::max(hi, glm::max(t.v0, glm::max(b, c)));
            const DVec3 centroid = t.v0 + (t.e1 + t.e2) / 3.0;
            clo = glm::min(clo, centroid);
            chi = glm::max(chi, centroid);
        }
        // Padded so that rounding in the slab test never culls a flat box its triangle hits.
        const DVec3 pad(1e-9 * extent_ + 1e-300);
        nodes_[index].lo = lo - pad;
        nodes_[index].hi = hi + pad;
        const DVec3 spread = chi - clo;
        const int axis = spread.x > spread.y ? (spread.x > spread.z ? 0 : 2) : (spread.y > spread.z ? 1 : 2);
        if (count <= 4 || spread[axis] <= 0.0) {
            nodes_[index].first = first;
            nodes_[index].count = count;
            return index;
        }
        const uint32_t half = count / 2;
        std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                         [&](uint32_t a, uint32_t b) {
                             const McTriangle& ta = triangles_[a];
                             const McTriangle& tb = triangles_[b];
                             const double ca = ta.v0[axis] * 3.0 + ta.e1[axis] + ta.e2[axis];
                             const double cb = tb.v0[axis] * 3.0 + tb.e1[axis] + tb.e2[axis];
                             return ca < cb || (ca == cb && a < b);
                         });
        // Children are allocated as a pair so inner nodes need one index.
        const uint32_t left = static_cast<uint32_t>(nodes_.size());
        nodes_.push_back({});
        nodes_.push_back({});
        nodes_[index].first = left;
        nodes_[index].count = 0;
        buildInto(left, first, half);
        buildInto(left + 1, first + half, count - half);
        return index;
    }

    void buildInto(uint32_t slot, uint32_t first, uint32_t count) {
        const uint32_t made = build(first, count);
        nodes_[slot] = nodes_[made];
        // `made` is now an orphan copy; harmless (a few wasted nodes) and keeps build simple.
    }

    std::vector<McTriangle> triangles_;
    std::vector<McLight> lights_;
    McSky sky_;
    std::vector<uint32_t> order_;
    std::vector<Node> nodes_;
    double extent_ = 0.0;
};

// splitmix64 as the generator: 2^64 period, passes BigCrush, trivially seedable per probe.
class McRandom {
public:
    explicit McRandom(uint64_t seed) : state_(seed) {}
    uint64_t next() {
        uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)

private:
    uint64_t state_;
};

// Cosine-weighted direction about unit n (Malley's method on an orthonormal frame).
inline DVec3 cosineDirection(const DVec3& n, McRandom& random) {
    const double u1 = random.uniform(), u2 = random.uniform();
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    const DVec3 helper = std::abs(n.x) > 0.9 ? DVec3(0, 1, 0) : DVec3(1, 0, 0);
    const DVec3 t = glm::normalize(glm::cross(helper, n));
    const DVec3 b = glm::cross(n, t);
    return glm::normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0, 1.0 - u1)));
}

struct McOptions {
    int samples = 4096;           // paths per probe
    bool next_event = true;       // light sampling + MIS at every vertex (see the top of this file)
    uint64_t seed = 1;
    int max_bounces = 1 << 20;    // safety net only: Russian roulette ends paths (rho < 1)
    int threads = 0;              // 0: hardware concurrency
};

struct McProbeResult {
    DVec3 irradiance{0.0};      // H, W/m^2
    DVec3 standard_error{0.0};  // of the mean, per channel
    uint64_t rays = 0;
};

// Picks points on the emitters: triangle t with probability w_t / W, w_t = A_t x max channel of
// L_e, then uniformly on t; so pdf_area(y) = max channel of L_e(t) / W.
class McEmitters {
public:
    explicit McEmitters(const McBvh& bvh) {
        const auto& tris = bvh.triangles();
        for (uint32_t i = 0; i < tris.size(); ++i) {
            const double le = std::max(tris[i].emission.x, std::max(tris[i].emission.y, tris[i].emission.z));
            if (!(le > 0.0)) continue;
            total_ += 0.5 * glm::length(glm::cross(tris[i].e1, tris[i].e2)) * le;
            index_.push_back(i);
            cdf_.push_back(total_);
        }
    }
    bool empty() const { return index_.empty(); }
    double total() const { return total_; }
    uint32_t pick(double u) const {
        const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u * total_);
        return index_[std::min<size_t>(it - cdf_.begin(), index_.size() - 1)];
    }

private:
    std::vector<uint32_t> index_;
    std::vector<double> cdf_;
    double total_ = 0.0;
};

// The share of light that gets along the ray from x along unit w to t_max (skipping `skip`): 0
// past an opaque triangle, else the product of the transmittances of those it crosses.
inline double segmentThrough(const McBvh& bvh, const DVec3& x, const DVec3& w, double t_max, uint32_t skip,
                             uint64_t& rays) {
    double through = 1.0, t_min = 0.0;
    for (;;) {
        ++rays;
        McHit hit;
        if (!bvh.closestHit(x, w, t_min, t_max, skip, hit)) return through;
        through *= bvh.triangles()[hit.triangle].transmittance;
        if (!(through > 0.0)) return 0.0;
        t_min = hit.t, skip = hit.triangle;
    }
}

// The surface a path along unit `dir` from `origin` meets: a transmitting one is passed with
// probability its transmittance (the light that crosses it keeps its direction), else met.
inline bool surfaceMet(const McBvh& bvh, const DVec3& origin, const DVec3& dir, uint32_t skip, McRandom& random,
                       McHit& hit, uint64_t& rays) {
    double t_min = 0.0;
    for (;;) {
        ++rays;
        if (!bvh.closestHit(origin, dir, t_min, std::numeric_limits<double>::infinity(), skip, hit)) return false;
        const double through = bvh.triangles()[hit.triangle].transmittance;
        if (!(through > 0.0) || random.uniform() >= through) return true;
        t_min = hit.t, skip = hit.triangle;
    }
}

// Light-sampling density per solid angle of emitter triangle `tri` seen at distance t under
// cos_y; 0 for a non-emitter.
inline double lightPdfSolidAngle(const McEmitters& emitters, const McTriangle& tri, double t, double cos_y) {
    const double le_max = std::max(tri.emission.x, std::max(tri.emission.y, tri.emission.z));
    if (!(le_max > 0.0) || !(cos_y > 0.0)) return 0.0;
    return le_max / emitters.total() * t * t / cos_y;
}

// Direct irradiance at (x, n) from one emitter sample, MIS-weighted (0 when hidden or facing away).
inline DVec3 sampleDirect(const McBvh& bvh, const McEmitters& emitters, const DVec3& x, const DVec3& n,
                          uint32_t skip, McRandom& random, uint64_t& rays) {
    const uint32_t index = emitters.pick(random.uniform());
    const McTriangle& light = bvh.triangles()[index];
    double u = random.uniform(), v = random.uniform();
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;  // fold the square onto the triangle: uniform
    const DVec3 y = light.v0 + light.e1 * u + light.e2 * v;
    const DVec3 to = y - x;
    const double r2 = glm::dot(to, to);
    if (!(r2 > 0.0)) return DVec3(0.0);
    const double r = std::sqrt(r2);
    const DVec3 w = to / r;
    const double cos_x = glm::dot(n, w), cos_y = faceMet(light, w).second;
    if (cos_x <= 0.0 || cos_y <= 0.0) return DVec3(0.0);
    const double eps = bvh.epsilon();
    const double through = r > 2.0 * eps ? segmentThrough(bvh, x, w, r - eps, skip, rays) : 1.0;
    if (!(through > 0.0)) return DVec3(0.0);
    const double p_light = lightPdfSolidAngle(emitters, light, r, cos_y), p_cosine = cos_x / kPi;
    // L_e cos_x / p_light, times the balance weight p_light / (p_light + p_cosine).
    return light.emission * (through * cos_x / (p_light + p_cosine));
}

// VRML97's spot factor at `angle` (radians) from the axis: 1 within the beam, 0 from the
// cut-off out, linear in the angle between; a beam wider than the cut-off ends at the cut-off.
inline double spotWeight(double angle, double beam_width, double cut_off_angle) {
    if (!(angle < cut_off_angle)) return 0.0;
    const double inner = std::min(beam_width, cut_off_angle);
    return angle <= inner ? 1.0 : (cut_off_angle - angle) / (cut_off_angle - inner);
}

// VRML97's attenuation 1 / max(a0 + a1 d + a2 d^2, 1), on top of the inverse-square law.
inline double distanceWeight(const DVec3& a, double d) { return 1.0 / std::max(1.0, a.x + d * (a.y + d * a.z)); }

// Irradiance at x (unit normal n) from one punctual light, with its shadow segment: exact,
// since a delta light has no area to sample.
inline DVec3 lightDirect(const McBvh& bvh, const McLight& light, const DVec3& x, const DVec3& n, uint32_t skip,
                         McRandom& random, uint64_t& rays) {
    if (light.type == LightType::Directional && light.cone_cos < 1.0) {
        // A direction uniform in the cone about -axis: pdf 1 / (2 pi (1 - cos a)); L_sun times
        // cos_x over that pdf is E 2 / (1 + cos a) cos_x.
        const double cos_t = 1.0 - random.uniform() * (1.0 - light.cone_cos), phi = 2.0 * kPi * random.uniform();
        const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
        const DVec3 w0 = -light.axis;
        const DVec3 helper = std::abs(w0.x) > 0.9 ? DVec3(0, 1, 0) : DVec3(1, 0, 0);
        const DVec3 e1 = glm::normalize(glm::cross(helper, w0)), e2 = glm::cross(w0, e1);
        const DVec3 w = glm::normalize(w0 * cos_t + (e1 * std::cos(phi) + e2 * std::sin(phi)) * sin_t);
        const double cos_x = glm::dot(n, w);
        if (!(cos_x > 0.0)) return DVec3(0.0);
        const double through = segmentThrough(bvh, x, w, std::numeric_limits<double>::infinity(), skip, rays);
        return light.strength * (through * 2.0 / (1.0 + light.cone_cos) * cos_x);
    }
    if (light.type == LightType::Directional) {
        const double cos_x = -glm::dot(n, light.axis);
        if (!(cos_x > 0.0)) return DVec3(0.0);
        const double through = segmentThrough(bvh, x, -light.axis, std::numeric_limits<double>::infinity(), skip, rays);
        return light.strength * (through * cos_x);
    }
    const DVec3 to = light.position - x;
    const double d = glm::length(to);
    if (!(d > 0.0) || d > light.radius) return DVec3(0.0);
    const DVec3 w = to / d;
    const double cos_x = glm::dot(n, w);
    if (!(cos_x > 0.0)) return DVec3(0.0);
    const double spot = light.type != LightType::Spot
                            ? 1.0
                            : spotWeight(std::acos(std::clamp(-glm::dot(w, light.axis), -1.0, 1.0)),
                                         light.beam_width, light.cut_off_angle);
    if (!(spot > 0.0)) return DVec3(0.0);
    // Stops short of the light by the offset, as the emitter samples do.
    const double eps = bvh.epsilon();
    const double through = d > 2.0 * eps ? segmentThrough(bvh, x, w, d - eps, skip, rays) : 1.0;
    return light.strength * (through * cos_x * spot * distanceWeight(light.attenuation, d) / (d * d));
}

// "No mesh" for a receiver: a probe has no place in the scene graph, so every light lights it.
inline constexpr uint32_t kMcAnyMesh = std::numeric_limits<uint32_t>::max();

// Direct irradiance at x on `mesh` from every punctual light that lights that mesh.
inline DVec3 punctualDirect(const McBvh& bvh, const DVec3& x, const DVec3& n, uint32_t skip, uint32_t mesh,
                            McRandom& random, uint64_t& rays) {
    DVec3 sum(0.0);
    for (const McLight& light : bvh.lights()) {
        const bool in_scope = mesh == kMcAnyMesh || !light.scoped ||
                              std::binary_search(light.scope.begin(), light.scope.end(), mesh);
        if (in_scope) sum += lightDirect(bvh, light, x, n, skip, random, rays);
    }
    return sum;
}

// One path's estimate of H at (p, n), with next-event estimation and MIS.
inline DVec3 tracePathNee(const McBvh& bvh, const McEmitters& emitters, const DVec3& p, const DVec3& n,
                          McRandom& random, int max_bounces, uint64_t& rays) {
    const double eps = bvh.epsilon();
    DVec3 origin = p + n * eps, normal = n;
    uint32_t skip = std::numeric_limits<uint32_t>::max(), mesh = kMcAnyMesh;
    DVec3 throughput(1.0), sum(0.0);
    if (emitters.empty() && !bvh.lit()) return sum;
    for (int bounce = 0; bounce <= max_bounces; ++bounce) {
        // The vertex's direct irradiance; times the throughput, which holds this vertex's rho,
        // that is its share of the radiance reflected back along the path.
        if (!emitters.empty()) sum += throughput * sampleDirect(bvh, emitters, origin, normal, skip, random, rays);
        sum += throughput * punctualDirect(bvh, origin, normal, skip, mesh, random, rays);
        McHit hit;
        const DVec3 dir = cosineDirection(normal, random);
        if (!surfaceMet(bvh, origin, dir, skip, random, hit, rays)) {
            sum += throughput * (kPi * bvh.sky().arriving(dir));  // left the scene: the sky (pdf cos / pi)
            break;
        }
        const McTriangle& tri = bvh.triangles()[hit.triangle];
        const auto [hit_normal, cos_y] = faceMet(tri, dir);
        if (cos_y <= 0.0) break;  // back face: black, absorbs
        const double p_cosine = glm::dot(normal, dir) / kPi;
        const double p_light = lightPdfSolidAngle(emitters, tri, hit.t, cos_y);
        // pi L_e (= L_e cos_x / p_cosine), times the balance weight p_cosine / (p_cosine + p_light).
        if (p_light > 0.0) sum += throughput * (kPi * tri.emission) * (p_cosine / (p_cosine + p_light));
        const double q = std::max(tri.reflectance.x, std::max(tri.reflectance.y, tri.reflectance.z));
        if (q <= 0.0 || random.uniform() >= q) break;
        throughput *= tri.reflectance / q;
        origin = origin + dir * hit.t + hit_normal * eps;
        normal = hit_normal;
        skip = hit.triangle;
        mesh = tri.mesh;
    }
    return sum;
}

// One path's estimate of H at (p, n), pure path tracing.
inline DVec3 tracePath(const McBvh& bvh, const DVec3& p, const DVec3& n, McRandom& random, int max_bounces,
                       uint64_t& rays) {
    const double eps = bvh.epsilon();
    DVec3 origin = p + n * eps;
    DVec3 dir = cosineDirection(n, random);
    uint32_t skip = std::numeric_limits<uint32_t>::max();
    DVec3 throughput(1.0);
    // Punctual lights cannot be hit by chance: they are always light-sampled, here too.
    DVec3 sum = punctualDirect(bvh, origin, n, skip, kMcAnyMesh, random, rays);
    for (int bounce = 0; bounce <= max_bounces; ++bounce) {
        McHit hit;
        if (!surfaceMet(bvh, origin, dir, skip, random, hit, rays)) {
            sum += throughput * (kPi * bvh.sky().arriving(dir));
            break;
        }
        const McTriangle& tri = bvh.triangles()[hit.triangle];
        const auto [hit_normal, cos_y] = faceMet(tri, dir);
        if (cos_y <= 0.0) break;  // back face: black, absorbs
        sum += throughput * (kPi * tri.emission);
        const double q = std::max(tri.reflectance.x, std::max(tri.reflectance.y, tri.reflectance.z));
        if (q <= 0.0 || random.uniform() >= q) break;
        throughput *= tri.reflectance / q;
        origin = origin + dir * hit.t + hit_normal * eps;
        skip = hit.triangle;
        sum += throughput * punctualDirect(bvh, origin, hit_normal, skip, tri.mesh, random, rays);
        dir = cosineDirection(hit_normal, random);
    }
    return sum;
}

inline uint64_t probeSeed(uint64_t seed, size_t probe) {
    McRandom mix(seed ^ (0xD1B54A32D192ED03ull * (static_cast<uint64_t>(probe) + 1)));
    return mix.next();
}

inline McProbeResult estimateProbe(const McBvh& bvh, const McEmitters& emitters, const DVec3& p,
                                   const DVec3& n_in, size_t probe_index, const McOptions& options) {
    McProbeResult result;
    const DVec3 n = glm::normalize(n_in);
    McRandom random(probeSeed(options.seed, probe_index));
    DVec3 sum(0.0), sum_sq(0.0);
    const int samples = std::max(1, options.samples);
    for (int s = 0; s < samples; ++s) {
        const DVec3 value = options.next_event
                                ? tracePathNee(bvh, emitters, p, n, random, options.max_bounces, result.rays)
                                : tracePath(bvh, p, n, random, options.max_bounces, result.rays);
        sum += value;
        sum_sq += value * value;
    }
    const double count = samples;
    result.irradiance = sum / count;
    if (samples > 1) {
        const DVec3 variance = glm::max(DVec3(0.0), (sum_sq - sum * sum / count) / (count - 1.0));
        result.standard_error = glm::sqrt(variance / count);
    }
    return result;
}

struct McProbe {
    DVec3 position{0.0};
    DVec3 normal{0.0, 0.0, 1.0};
};

// Every probe, on options.threads threads; the result does not depend on the thread count.
inline std::vector<McProbeResult> estimateProbes(const McBvh& bvh, const std::vector<McProbe>& probes,
                                                 const McOptions& options) {
    std::vector<McProbeResult> results(probes.size());
    const McEmitters emitters(bvh);
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t i = next++; i < probes.size(); i = next++)
            results[i] = estimateProbe(bvh, emitters, probes[i].position, probes[i].normal, i, options);
    };
    int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::clamp(threads, 1, 256);
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    return results;
}

}  // namespace radbake::reference
