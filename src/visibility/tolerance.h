#pragma once
// Rounding tolerances of the shaft and occlusion tests (internal to src/visibility).
//
// Every test evaluates plane functions n.p + d in double on points whose coordinates are at
// most `scale` in magnitude (|n| = 1). Each evaluation (a 3-term dot product plus an offset)
// and each constructed point or plane (corners, cross products, normalisation, segment/plane
// intersections) carries a relative error of a few units of eps = 2^-53 of `scale`; chains
// of at most ~10 such operations stay below 32 eps scale. We use 64 eps scale (1.4e-14 of
// the coordinates' magnitude): far below any geometric feature, and always applied on the
// safe side (crossing tests widen the shaft; occlusion tests demand that much inside).
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/math.h"

namespace radbake {

inline constexpr double kRoundingUnits = 64.0;

inline double shaftTolerance(double scale) {
    return kRoundingUnits * std::numeric_limits<double>::epsilon() * scale;
}

inline double maxAbs(const DVec3& p) {
    return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

}  // namespace radbake
