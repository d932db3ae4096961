#include "scene/environment_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace radbake {
namespace {

double luminance(const float* rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

// Elevation (radians) of the top edge of row `y` (y may be fractional or H: the bottom edge).
double rowEdgeElevation(const EnvironmentMap& map, double y) { return 0.5 * kPi - kPi * y / map.height; }

// The solid angle of texel row y, per texel.
double texelSolidAngle(const EnvironmentMap& map, int y) {
    return (2.0 * kPi / map.width) *
           (std::sin(rowEdgeElevation(map, y)) - std::sin(rowEdgeElevation(map, y + 1.0)));
}

DVec3 texelDirection(const EnvironmentMap& map, const MapFrame& frame, double x, double y) {
    const double azimuth = 2.0 * kPi * x / map.width - kPi, elevation = rowEdgeElevation(map, y);
    return std::cos(elevation) * (std::cos(azimuth) * frame.azimuth0 + std::sin(azimuth) * frame.azimuth90) +
           std::sin(elevation) * frame.up;
}

// Continuous map coordinates of a unit direction: x in [0, width), y in [0, height].
DVec2 mapCoordinates(const EnvironmentMap& map, const MapFrame& frame, const DVec3& d) {
    const double up = std::clamp(glm::dot(d, frame.up), -1.0, 1.0);
    const double azimuth = std::atan2(glm::dot(d, frame.azimuth90), glm::dot(d, frame.azimuth0));
    double x = (azimuth + kPi) / (2.0 * kPi) * map.width;
    if (x >= map.width) x -= map.width;
    return {std::max(0.0, x), (0.5 * kPi - std::asin(up)) / kPi * map.height};
}

void buildIntegral(EnvironmentMap& map) {
    const size_t corners = size_t(map.width) + 1;
    map.integral.assign(corners * (size_t(map.height) + 1) * 3, 0.0);
    for (int y = 0; y < map.height; ++y) {
        const double omega = texelSolidAngle(map, y);
        double row[3] = {0.0, 0.0, 0.0};
        for (int x = 0; x < map.width; ++x) {
            const float* texel = &map.rgb[(size_t(y) * map.width + x) * 3];
            for (int c = 0; c < 3; ++c) {
                row[c] += double(texel[c]) * omega;
                const size_t at = ((y + 1) * corners + x + 1) * 3 + c;
                map.integral[at] = map.integral[at - corners * 3] + row[c];
            }
        }
    }
}

// The integral table at continuous corner coordinates (x, y), bilinear between corners: exact
// over whole texels, and linear across a texel's width and height.
DVec3 integralAt(const EnvironmentMap& map, double x, double y) {
    const size_t corners = size_t(map.width) + 1;
    x = std::clamp(x, 0.0, double(map.width)), y = std::clamp(y, 0.0, double(map.height));
    const int x0 = std::min(int(x), map.width - 1), y0 = std::min(int(y), map.height - 1);
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int xx, int yy) {
        const double* p = &map.integral[(size_t(yy) * corners + xx) * 3];
        return DVec3(p[0], p[1], p[2]);
    };
    return (at(x0, y0) * (1 - fx) + at(x0 + 1, y0) * fx) * (1 - fy) +
           (at(x0, y0 + 1) * (1 - fx) + at(x0 + 1, y0 + 1) * fx) * fy;
}

// The solid angle the table holds over [x0, x1] x [y0, y1], linear across a texel as integralAt is,
// so that a constant map averages to its constant exactly.
double solidAngleOf(const EnvironmentMap& map, double x0, double x1, double y0, double y1) {
    auto rowsAbove = [&](double y) {
        y = std::clamp(y, 0.0, double(map.height));
        const int whole = std::min(int(y), map.height - 1);
        const double above = 1.0 - std::sin(rowEdgeElevation(map, whole));  // per unit 2 pi of azimuth
        const double within = std::sin(rowEdgeElevation(map, whole)) - std::sin(rowEdgeElevation(map, whole + 1.0));
        return above + within * (y - whole);
    };
    return (2.0 * kPi / map.width) * (x1 - x0) * (rowsAbove(y1) - rowsAbove(y0));
}

DVec3 integralOver(const EnvironmentMap& map, double x0, double x1, double y0, double y1) {
    return integralAt(map, x1, y1) - integralAt(map, x0, y1) - integralAt(map, x1, y0) + integralAt(map, x0, y0);
}

}  // namespace

EnvironmentMap makeEnvironmentMap(int width, int height, std::vector<float> rgb, std::string path) {
    EnvironmentMap map;
    map.width = width, map.height = height, map.rgb = std::move(rgb), map.path = std::move(path);
    buildIntegral(map);
    return map;
}

DVec3 mapRadiance(const EnvironmentMap& map, const MapFrame& frame, const DVec3& direction) {
    const DVec2 at = mapCoordinates(map, frame, direction);
    const int x = std::min(int(at.x), map.width - 1), y = std::min(int(at.y), map.height - 1);
    const float* texel = &map.rgb[(size_t(y) * map.width + x) * 3];
    return DVec3(texel[0], texel[1], texel[2]);
}

DVec3 mapRadianceOver(const EnvironmentMap& map, const MapFrame& frame, const DVec3& direction, double solid_angle) {
    const DVec2 at = mapCoordinates(map, frame, direction);
    const double side = std::sqrt(std::max(0.0, solid_angle));
    const double elevation = 0.5 * kPi - kPi * at.y / map.height;
    const double half_width = 0.5 * side / std::max(1e-9, std::cos(elevation));
    const double W = map.width, H = map.height;
    double y0 = at.y - 0.5 * side / kPi * H, y1 = at.y + 0.5 * side / kPi * H;
    double x0 = at.x - half_width / (2.0 * kPi) * W, x1 = at.x + half_width / (2.0 * kPi) * W;
    if (y0 <= 0.0 || y1 >= H || x1 - x0 >= W) {
        // A cap about the pole the patch reaches, of the patch's solid angle.
        const double sin_edge = std::max(-1.0, 1.0 - solid_angle / (2.0 * kPi));
        const double edge_y = (0.5 * kPi - std::asin(sin_edge)) / kPi * H;
        x0 = 0.0, x1 = W;
        if (at.y < 0.5 * H) y0 = 0.0, y1 = std::max(edge_y, 1e-9);
        else y0 = std::min(H - edge_y, H - 1e-9), y1 = H;
    }
    DVec3 sum(0.0);
    double omega = 0.0;
    auto add = [&](double a, double b) {
        sum += integralOver(map, a, b, y0, y1);
        omega += solidAngleOf(map, a, b, y0, y1);
    };
    if (x0 < 0.0) add(x0 + W, W), add(0.0, x1);
    else if (x1 > W) add(x0, W), add(0.0, x1 - W);
    else add(x0, x1);
    if (!(omega > 0.0)) return mapRadiance(map, frame, direction);
    return glm::max(sum / omega, DVec3(0.0));
}

DVec3 mapTotal(const EnvironmentMap& map) { return integralAt(map, map.width, map.height); }

std::vector<MapSun> extractSuns(EnvironmentMap& map, const MapFrame& frame, double threshold, double max_diameter,
                                size_t max_suns) {
    const size_t texels = size_t(map.width) * map.height;
    // The mean luminance of the texels up to `limit`.
    auto meanUpTo = [&](double limit) {
        double sum = 0.0, omega = 0.0;
        for (int y = 0; y < map.height; ++y) {
            const double texel_omega = texelSolidAngle(map, y);
            for (int x = 0; x < map.width; ++x) {
                const double y_lum = luminance(&map.rgb[(size_t(y) * map.width + x) * 3]);
                if (y_lum <= limit) sum += y_lum * texel_omega, omega += texel_omega;
            }
        }
        return omega > 0.0 ? sum / omega : 0.0;
    };
    // Relative to the sky without its suns: a sun holds much of a clear sky's light.
    const double bright = threshold * meanUpTo(threshold * meanUpTo(std::numeric_limits<double>::infinity()));
    if (!(bright > 0.0)) return {};
    auto isBright = [&](size_t i) { return luminance(&map.rgb[i * 3]) > bright; };

    // Connected groups of bright texels (8-neighbours, wrapping around in azimuth).
    struct Group {
        std::vector<size_t> members;
        double excess = 0.0;  // luminance times solid angle beyond the threshold
    };
    std::vector<Group> groups;
    std::vector<uint8_t> visited(texels, 0);
    std::vector<size_t> stack;
    for (size_t start = 0; start < texels; ++start) {
        if (visited[start] || !isBright(start)) continue;
        Group group;
        visited[start] = 1;
        stack.push_back(start);
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            group.members.push_back(i);
            const int x = int(i % map.width), y = int(i / map.width);
            group.excess += (luminance(&map.rgb[i * 3]) - bright) * texelSolidAngle(map, y);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int ny = y + dy, nx = (x + dx + map.width) % map.width;
                    if (ny < 0 || ny >= map.height) continue;
                    const size_t j = size_t(ny) * map.width + nx;
                    if (!visited[j] && isBright(j)) visited[j] = 1, stack.push_back(j);
                }
        }
        groups.push_back(std::move(group));
    }
    std::stable_sort(groups.begin(), groups.end(), [](const Group& a, const Group& b) { return a.excess > b.excess; });

    std::vector<MapSun> suns;
    for (const Group& group : groups) {
        if (suns.size() == max_suns) break;
        double omega = 0.0;
        for (const size_t i : group.members) omega += texelSolidAngle(map, int(i / map.width));
        const double diameter = 2.0 * std::acos(std::clamp(1.0 - omega / (2.0 * kPi), -1.0, 1.0));
        if (diameter > max_diameter) continue;  // a bright patch of sky, not a sun: it stays in the map
        MapSun sun;
        DVec3 towards(0.0);
        for (const size_t i : group.members) {
            float* texel = &map.rgb[i * 3];
            const int x = int(i % map.width), y = int(i / map.width);
            const double keep = bright / luminance(texel), texel_omega = texelSolidAngle(map, y);
            const DVec3 excess = DVec3(texel[0], texel[1], texel[2]) * (1.0 - keep);
            sun.irradiance += excess * texel_omega;
            towards += (luminance(texel) - bright) * texel_omega * texelDirection(map, frame, x + 0.5, y + 0.5);
            for (int c = 0; c < 3; ++c) texel[c] = static_cast<float>(texel[c] * keep);
        }
        sun.direction = glm::normalize(towards);
        sun.angular_diameter = diameter;
        sun.texels = group.members.size();
        suns.push_back(sun);
    }
    if (!suns.empty()) buildIntegral(map);
    return suns;
}

}  // namespace radbake
