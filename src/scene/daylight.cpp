#include "scene/daylight.h"

#include <algorithm>
#include <charconv>
#include <limits>
#include <cctype>
#include <cmath>

namespace radbake {
namespace {

constexpr double kDegree = kPi / 180.0;

// The axis index (0 x, 1 y, 2 z) of a unit axis vector.
int axisOf(const Vec3& up) { return std::abs(up.x) > 0.5f ? 0 : std::abs(up.y) > 0.5f ? 1 : 2; }

// Azimuth 0 and azimuth 90 about `up` (the orientation convention in daylight.h).
void horizonAxes(const Vec3& up, DVec3& east, DVec3& north) {
    const int a = axisOf(up);
    const int first = a == 0 ? 1 : 0, second = a == 2 ? 1 : 2;
    const double sign = (up[a] < 0.0f) ? -1.0 : 1.0;
    east = DVec3(0.0), north = DVec3(0.0);
    east[first] = 1.0;
    north[second] = sign;
}

std::optional<double> parseNumber(std::string_view text) {
    while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
    while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    double value = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        return std::nullopt;
    return value;
}

}  // namespace

std::optional<SkyModel> parseSkyModel(std::string_view text) {
    if (text == "none") return SkyModel::None;
    if (text == "uniform") return SkyModel::Uniform;
    if (text == "overcast") return SkyModel::Overcast;
    if (text == "background") return SkyModel::Background;
    if (text.size() > 4) {
        std::string suffix(text.substr(text.size() - 4));
        for (char& c : suffix) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (suffix == ".exr") return SkyModel::Map;
    }
    return std::nullopt;
}

const char* skyModelName(SkyModel model) {
    switch (model) {
        case SkyModel::None: return "none";
        case SkyModel::Uniform: return "uniform";
        case SkyModel::Overcast: return "overcast";
        case SkyModel::Background: return "background";
        case SkyModel::Map: return "map";
    }
    return "none";
}

std::optional<Vec3> parseUpAxis(std::string_view text) {
    if (text.size() != 2 || (text[0] != '+' && text[0] != '-')) return std::nullopt;
    const float sign = text[0] == '+' ? 1.0f : -1.0f;
    switch (text[1]) {
        case 'x': return Vec3(sign, 0.0f, 0.0f);
        case 'y': return Vec3(0.0f, sign, 0.0f);
        case 'z': return Vec3(0.0f, 0.0f, sign);
        default: return std::nullopt;
    }
}

std::string upAxisName(const Vec3& up) {
    const int a = axisOf(up);
    return std::string(up[a] < 0.0f ? "-" : "+") + "xyz"[a];
}

std::optional<SunPosition> parseSunPosition(std::string_view text) {
    const size_t comma = text.find(',');
    if (comma == std::string_view::npos) return std::nullopt;
    const std::optional<double> azimuth = parseNumber(text.substr(0, comma));
    const std::optional<double> elevation = parseNumber(text.substr(comma + 1));
    if (!azimuth || !elevation || *elevation < -90.0 || *elevation > 90.0) return std::nullopt;
    return SunPosition{*azimuth, *elevation};
}

MapFrame mapFrame(const Vec3& up) {
    MapFrame frame;
    frame.up = DVec3(up);
    horizonAxes(up, frame.azimuth0, frame.azimuth90);
    return frame;
}

DVec3 sunDirection(const SunPosition& sun, const Vec3& up) {
    DVec3 east, north;
    horizonAxes(up, east, north);
    const double azimuth = sun.azimuth_degrees * kDegree, elevation = sun.elevation_degrees * kDegree;
    return glm::normalize(std::cos(elevation) * (std::cos(azimuth) * east + std::sin(azimuth) * north) +
                          std::sin(elevation) * DVec3(up));
}

std::string checkDaylight(const DaylightOptions& o) {
    if (o.sky == SkyModel::Map && o.sky_map.empty()) return "--sky: an environment map needs its file";
    if (!(o.sky_radiance >= 0.0) || !std::isfinite(o.sky_radiance))
        return "--sky-radiance must be a non-negative finite number";
    if (!(o.sun_irradiance >= 0.0) || !std::isfinite(o.sun_irradiance))
        return "--sun-irradiance must be a non-negative finite number";
    if (!(o.sun_diameter_degrees >= 0.0 && o.sun_diameter_degrees <= 90.0))
        return "--sun-diameter must be in [0, 90] degrees";
    if (glm::length(DVec3(o.up)) != 1.0 || std::abs(o.up.x) + std::abs(o.up.y) + std::abs(o.up.z) != 1.0f)
        return "--up must be one of +x, -x, +y, -y, +z, -z";
    if (o.sun && (!std::isfinite(o.sun->azimuth_degrees) || !(std::abs(o.sun->elevation_degrees) <= 90.0)))
        return "--sun needs a finite azimuth and an elevation in [-90, 90] degrees";
    return {};
}

namespace {

// A directional light over every mesh, towards `towards`, of irradiance `irradiance` (per channel).
Light daylightSun(const DVec3& towards, const DVec3& irradiance, double angular_diameter) {
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = Vec3(-towards);
    const double peak = std::max(irradiance.x, std::max(irradiance.y, irradiance.z));
    sun.intensity = static_cast<float>(peak);
    sun.color = peak > 0.0 ? Vec3(irradiance / peak) : Vec3(1.0f);
    sun.angular_diameter = static_cast<float>(angular_diameter);
    sun.radius = std::numeric_limits<float>::infinity();
    return sun;
}

}  // namespace

std::string addDaylight(Scene& scene, const DaylightOptions& options, std::shared_ptr<EnvironmentMap> map,
                        size_t* suns_taken) {
    if (options.sky == SkyModel::Background) {
        if (!scene.background) return "--sky background: the scene has no VRML97 Background node";
        scene.sky.background = *scene.background;
    }
    if (options.sky == SkyModel::Map) {
        if (!map || map->width < 1 || map->height < 1) return "--sky " + options.sky_map + ": no environment map read";
        const std::vector<MapSun> suns = extractSuns(*map, mapFrame(options.up));
        for (size_t k = 0; k < suns.size(); ++k) {
            scene.lights.push_back(daylightSun(suns[k].direction, suns[k].irradiance * options.sky_radiance, suns[k].angular_diameter));
            scene.lights.back().name = "map sun " + std::to_string(k + 1);
        }
        if (suns_taken) *suns_taken = suns.size();
        scene.sky.map = std::move(map);
    }
    if (options.sky != SkyModel::None) {
        scene.sky.model = options.sky;
        scene.sky.radiance = Vec3(static_cast<float>(options.sky_radiance));
        scene.sky.up = options.up;
    }
    if (options.sun) {
        scene.lights.push_back(daylightSun(sunDirection(*options.sun, options.up), DVec3(options.sun_irradiance),
                                           options.sun_diameter_degrees * kDegree));
        scene.lights.back().name = "sun";
    }
    return {};
}

namespace {

// The colour at `angle` along a VRML97 Background's colour ramp (angles[i - 1] holds colours[i]).
Vec3 rampColour(const std::vector<float>& angles, const std::vector<Vec3>& colours, double angle) {
    if (colours.empty()) return Vec3(0.0f);
    if (angles.empty() || angle <= 0.0) return colours[0];
    for (size_t i = 0; i < angles.size() && i + 1 < colours.size(); ++i) {
        const double from = i == 0 ? 0.0 : angles[i - 1], to = angles[i];
        if (angle <= to) {
            const double w = to > from ? (angle - from) / (to - from) : 1.0;
            return colours[i] + float(std::clamp(w, 0.0, 1.0)) * (colours[i + 1] - colours[i]);
        }
    }
    return colours[std::min(angles.size(), colours.size() - 1)];
}

}  // namespace

DVec3 skyRadiance(const Sky& sky, const DVec3& direction) {
    const double cos_zenith = glm::dot(direction, DVec3(sky.up));
    if (sky.model == SkyModel::Map)
        return sky.map ? DVec3(sky.radiance) * mapRadiance(*sky.map, mapFrame(sky.up), direction) : DVec3(0.0);
    if (sky.model == SkyModel::Background) {
        const BackgroundSky& b = sky.background;
        const double zenith = std::acos(std::clamp(cos_zenith, -1.0, 1.0)), nadir = kPi - zenith;
        // The ground is drawn over the sky up to its last angle (with at least two colours).
        if (!b.ground_color.empty() && !b.ground_angle.empty() && nadir <= b.ground_angle.back())
            return DVec3(sky.radiance) * DVec3(rampColour(b.ground_angle, b.ground_color, nadir));
        if (!b.ground_color.empty() && b.ground_angle.empty() && nadir <= 0.0)
            return DVec3(sky.radiance) * DVec3(b.ground_color[0]);
        return DVec3(sky.radiance) * DVec3(rampColour(b.sky_angle, b.sky_color, zenith));
    }
    if (!(cos_zenith > 0.0)) return DVec3(0.0);
    switch (sky.model) {
        case SkyModel::None: return DVec3(0.0);
        case SkyModel::Uniform: return DVec3(sky.radiance);
        case SkyModel::Overcast: return DVec3(sky.radiance) * ((1.0 + 2.0 * cos_zenith) / 3.0);
        case SkyModel::Background:
        case SkyModel::Map: break;
    }
    return DVec3(0.0);
}

DVec3 skyRadianceOver(const Sky& sky, const DVec3& direction, double solid_angle) {
    if (sky.model == SkyModel::Map && sky.map)
        return DVec3(sky.radiance) * mapRadianceOver(*sky.map, mapFrame(sky.up), direction, solid_angle);
    return skyRadiance(sky, direction);
}

}  // namespace radbake
