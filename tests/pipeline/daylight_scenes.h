#pragma once
// Scenes and checks the daylight tests share: quads over a black ground, a bake with a sky, sun or
// environment map and probes, a relative check.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "radbake.h"
#include "../export/temp_files.h"

namespace daylight_test {

using namespace radbake;
using testfs::TempDir;

inline constexpr double kDegree = kPi / 180.0;

inline std::string material(double rho) {
    const std::string r = std::to_string(rho);
    return "appearance Appearance { material Material { diffuseColor " + r + " " + r + " " + r + " } }";
}

// A quad (corners in order, counter-clockwise seen from its front), one-sided unless `two_sided`.
inline std::string quad(const std::vector<DVec3>& corners, double rho, bool two_sided = false) {
    std::string points;
    for (const DVec3& c : corners)
        points += std::to_string(c.x) + " " + std::to_string(c.y) + " " + std::to_string(c.z) + ", ";
    return "Shape { " + material(rho) + " geometry IndexedFaceSet { solid " + (two_sided ? "FALSE" : "TRUE") +
           " coord Coordinate { point [ " + points + "] } coordIndex [ 0 1 2 3 -1 ] } }\n";
}

// A black pane letting `t` of the light through: VRML transparency.
inline std::string pane(const std::vector<DVec3>& corners, double t) {
    std::string points;
    for (const DVec3& c : corners)
        points += std::to_string(c.x) + " " + std::to_string(c.y) + " " + std::to_string(c.z) + ", ";
    return "Shape { appearance Appearance { material Material { diffuseColor 0 0 0 transparency " + std::to_string(t) +
           " } } geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ " + points +
           "] } coordIndex [ 0 1 2 3 -1 ] } }\n";
}

// A black ground y = 0, x and z in [-50, 50], facing up.
inline const std::string kBlackGround = quad({{-50, 0, -50}, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}}, 0.0);

inline Bake bakeWith(const TempDir& dir, const std::string& body, const DaylightOptions& daylight,
              const std::vector<Probe>& probes, Quality quality = Quality::Medium) {
    BakeOptions options = BakeOptions::forQuality(quality);
    options.import.daylight = daylight;
    options.lightmaps.enabled = false;
    options.probes = probes;
    options.threading.threads = 2;
    Progress progress(false);
    Diagnostics diagnostics;
    Bake baked = bake(testfs::writeText(dir, "daylight.wrl", "#VRML V2.0 utf8\n" + body), options, progress,
                      diagnostics);
    REQUIRE(std::string(toString(baked.status)) == "ok");
    REQUIRE(baked.probe_irradiance.size() == probes.size());
    return baked;
}

inline Probe probe(const DVec3& position, const DVec3& normal) { return Probe{position, glm::normalize(normal), {}}; }

inline void checkWithin(double value, double expected, double relative, const std::string& what) {
    INFO(what << ": " << value << " against " << expected);
    CHECK(std::abs(value - expected) <= relative * std::abs(expected));
}

}  // namespace daylight_test
