#pragma once
// An equirectangular environment map (--sky FILE.exr): linear RGB radiance over the whole sphere,
// each texel a constant radiance over its cell of azimuth and elevation.
//
// Orientation, as three.js and most Y-up engines read such maps: the top row looks at the zenith
// (Sky::up), the bottom row at the nadir; the centre column looks towards azimuth 0 and azimuth
// grows to the right, as --sun's does (scene/daylight.h), so a sun drawn at column x (0 at the
// left edge) of a map W texels wide stands at azimuth 360 (x + 0.5) / W - 180 degrees.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"

namespace radbake {

struct EnvironmentMap {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // W sr^-1 m^-2 per channel, row-major, top row first
    // Radiance times solid angle summed over the texels above and left of each texel corner:
    // (height + 1) rows of (width + 1) corners, 3 channels each.
    std::vector<double> integral;
    std::string path;  // the file, as given
};

// The directions the map's columns and rows are laid out by: the zenith and azimuths 0 and 90.
struct MapFrame {
    DVec3 up, azimuth0, azimuth90;
};

// A map over `rgb` (width * height * 3, finite and non-negative), its integral built.
EnvironmentMap makeEnvironmentMap(int width, int height, std::vector<float> rgb, std::string path);

// The radiance of the texel `direction` (unit, world) falls in.
DVec3 mapRadiance(const EnvironmentMap& map, const MapFrame& frame, const DVec3& direction);

// The mean radiance over a patch of about `solid_angle` steradians about `direction`, bounded by
// azimuths and elevations (a cap about the pole it reaches): what a quadrature sample standing for
// that much of the sphere reads, so a detail smaller than the sample's spacing is neither missed
// nor counted as if it filled the sample's cell.
DVec3 mapRadianceOver(const EnvironmentMap& map, const MapFrame& frame, const DVec3& direction, double solid_angle);

// The integral of radiance over the whole sphere, per channel (W m^-2 sr^-1 times sr).
DVec3 mapTotal(const EnvironmentMap& map);

// A sun drawn in the map, taken out of it as a directional light.
struct MapSun {
    DVec3 direction{0.0};   // unit, world, towards the sun
    DVec3 irradiance{0.0};  // W/m^2 per channel on a plane facing it
    double angular_diameter = 0.0;  // radians: a disc of the solid angle its texels cover
    size_t texels = 0;
};

// Takes the suns out of `map`: each connected group of texels brighter than `threshold` times the
// mean luminance of the sky without them (of the texels up to `threshold` times the map's mean),
// subtending at most `max_diameter` radians, becomes a MapSun carrying what
// its texels hold beyond the threshold; the texels keep the threshold's worth (their colour kept),
// so the map and its suns together hold what the map held. A sun in a map is a few texels of
// enormous radiance: left in, a quadrature would see it whole or not at all from sample to
// sample; as a directional light it casts the shadows its size gives. At most `max_suns`, the
// brightest first; the map's integral is rebuilt.
std::vector<MapSun> extractSuns(EnvironmentMap& map, const MapFrame& frame, double threshold = 100.0,
                                double max_diameter = 0.2, size_t max_suns = 4);

}  // namespace radbake
