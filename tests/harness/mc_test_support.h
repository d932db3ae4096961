#pragma once
// Checks shared by the reference estimator's tests.
#include <doctest/doctest.h>

#include <vector>

#include "reference_mc.h"

namespace radbake::mctest {

// The same bits on 1 and 3 threads (each probe's random stream depends only on seed and probe);
// returns the 1-thread results.
inline std::vector<reference::McProbeResult> checkSameOnThreadCounts(const reference::McBvh& bvh,
                                                                     const std::vector<reference::McProbe>& probes,
                                                                     reference::McOptions options) {
    options.threads = 1;
    const auto one = reference::estimateProbes(bvh, probes, options);
    options.threads = 3;
    const auto three = reference::estimateProbes(bvh, probes, options);
    for (size_t i = 0; i < probes.size(); ++i) {
        CHECK(one[i].irradiance == three[i].irradiance);
        CHECK(one[i].rays == three[i].rays);
    }
    return one;
}

}  // namespace radbake::mctest
