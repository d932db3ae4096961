#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "core/progress.h"

using namespace radbake;

// Times here are what a test cannot control; the checks hold for any elapsed time below an hour.
TEST_CASE("a stage's fraction is unknown until it knows what follows, then counts what setAhead expects") {
    Progress progress(false);
    std::vector<ProgressEvent> events;
    std::vector<std::string> stages;
    progress.setSink([&](const ProgressEvent& e) {
        events.push_back(e);
        stages.emplace_back(e.stage);
    });
    progress.beginPhase("before");  // not in a stage
    progress.update(0.5);
    progress.beginStage("the solve");
    progress.beginPhase("links");
    REQUIRE(!events.empty());
    CHECK(stages.back() == "the solve");
    CHECK(events.back().stage_fraction == 0.0);  // nothing told of what follows

    progress.setAhead(3600.0);  // an hour after this phase
    progress.endPhase();        // the phase done: what is left is the hour ahead
    CHECK(events.back().phase_done);
    CHECK(events.back().stage_fraction > 0.0);
    CHECK(events.back().stage_fraction < 0.01);
    CHECK(events.back().stage_seconds_left == doctest::Approx(3600.0));

    progress.beginPhase("solve");
    progress.setAhead(0.0);  // nothing after it
    progress.endPhase();
    CHECK(events.back().stage_fraction == doctest::Approx(1.0));
    CHECK(events.back().stage_seconds_left == 0.0);
    // More work found later says so in the time left, but the fraction never falls back.
    progress.beginPhase("more");
    progress.setAhead(3600.0);
    progress.endPhase();
    CHECK(events.back().stage_fraction == doctest::Approx(1.0));
    CHECK(events.back().stage_seconds_left == doctest::Approx(3600.0));
    progress.endStage();
    progress.beginPhase("after");
    CHECK(stages.back().empty());
    CHECK(stages.front().empty());
}
