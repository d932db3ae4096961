#pragma once
// Daylight: a sky and a sun over the scene, chosen by the user rather than read from the file
// (ImportOptions::daylight, --sky, --sun). The import turns them into Scene::sky and a
// directional Light with a disc (Light::angular_diameter); the solve and the read-out light
// with them as with the file's lights (radiosity/sky_light.h).
//
// Orientation. `up` orients the sky and the sun only; the geometry is not moved. The sun's
// azimuth turns about `up` from the first of x, y, z that is not the up axis (azimuth 0)
// towards the other one (azimuth 90), that one negated when up is negative: up +y turns from +x
// towards +z, up +z from +x towards +y, up +x from +y towards +z, up -y from +x towards -z.
#include <optional>
#include <string>
#include <string_view>

#include "core/math.h"
#include "scene/scene.h"

namespace radbake {

struct SunPosition {
    double azimuth_degrees = 0.0;
    double elevation_degrees = 45.0;  // above the horizon
};

struct DaylightOptions {
    SkyModel sky = SkyModel::None;
    // SkyModel::Map: the equirectangular EXR environment map (scene/environment_map.h), as given.
    std::string sky_map;
    // W sr^-1 m^-2: the uniform sky's radiance, the overcast sky's zenith radiance.
    double sky_radiance = 1.0;
    Vec3 up{0.0f, 1.0f, 0.0f};  // a unit axis (parseUpAxis)
    std::optional<SunPosition> sun;
    // W/m^2 on a plane facing the sun. The default keeps a clear day's proportion to the default
    // sky: about 800 W/m^2 of direct sun against 100 W/m^2 of sky light on the ground.
    double sun_irradiance = 25.0;
    double sun_diameter_degrees = 0.53;

    bool any() const { return sky != SkyModel::None || sun.has_value(); }
};

// "uniform", "overcast", "background" (and "none"), or a file name ending in ".exr" (any case):
// SkyModel::Map; nullopt for anything else.
std::optional<SkyModel> parseSkyModel(std::string_view text);
const char* skyModelName(SkyModel model);
// "+y", "-z", ... (a sign is required); nullopt for anything else.
std::optional<Vec3> parseUpAxis(std::string_view text);
std::string upAxisName(const Vec3& up);
// "AZIMUTH,ELEVATION" in degrees, both finite, elevation in [-90, 90]; nullopt otherwise.
std::optional<SunPosition> parseSunPosition(std::string_view text);

// Azimuth 0 and azimuth 90 about `up` (the orientation convention above), with `up`: how an
// environment map's columns and rows lie.
MapFrame mapFrame(const Vec3& up);

// Unit vector towards the sun (the orientation convention above).
DVec3 sunDirection(const SunPosition& sun, const Vec3& up);

// An empty string when the options are usable, else what is wrong (for a located error).
std::string checkDaylight(const DaylightOptions& options);

// Sets scene.sky and appends the sun (a directional Light lighting every mesh) as the options say;
// what is wrong (--sky background without a Background node) when it cannot, else empty. With
// SkyModel::Map, `map` is the environment map read from options.sky_map: the suns drawn in it are
// taken out as directional lights too (extractSuns), their number in `suns_taken`.
std::string addDaylight(Scene& scene, const DaylightOptions& options, std::shared_ptr<EnvironmentMap> map = {},
                        size_t* suns_taken = nullptr);

// The sky's radiance arriving from unit `direction` (travelling against it): for the uniform and
// overcast skies 0 at and below the horizon, the uniform sky's radiance above it, the CIE overcast
// sky's L(theta) = Lz (1 + 2 cos theta) / 3 (theta from the zenith); for a Background its
// colours over the whole sphere (BackgroundSky) times Sky::radiance.
// An environment map's texel (times Sky::radiance) holding the direction.
DVec3 skyRadiance(const Sky& sky, const DVec3& direction);

// skyRadiance averaged over a patch of about `solid_angle` steradians about `direction` where the
// sky has detail a point would miss (an environment map: mapRadianceOver), else skyRadiance.
DVec3 skyRadianceOver(const Sky& sky, const DVec3& direction, double solid_angle);

}  // namespace radbake
