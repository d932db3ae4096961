#include <doctest/doctest.h>

#include "core/diagnostics.h"

using namespace radbake;

TEST_CASE("diagnostics format as file:line:col: severity: message") {
    Diagnostics diagnostics;
    std::vector<std::string> printed;
    diagnostics.sink = [&](const Diagnostic& d) { printed.push_back(formatDiagnostic(d)); };
    diagnostics.error({"a.wrl", 3, 7}, "bad thing");
    diagnostics.warning({"b.obj", 0, 0}, "odd thing");
    diagnostics.warning({}, "no place");
    CHECK(diagnostics.errorCount() == 1);
    CHECK(diagnostics.warningCount() == 2);
    REQUIRE(printed.size() == 3);
    CHECK(printed[0] == "a.wrl:3:7: error: bad thing");
    CHECK(printed[1] == "b.obj: warning: odd thing");
    CHECK(printed[2] == "warning: no place");
}

