#pragma once
// Irradiance probes: a text file in, probes.csv out.
//
// Input: one probe a line, `x y z nx ny nz`, separated by spaces, tabs or single commas;
// `#` starts a comment; blank lines are skipped. Positions are in the scene file's units
// (the bake applies --unit-scale); normals need not be unit length but must not be zero.
// Output: header `x,y,z,nx,ny,nz,r,g,b`, then one line per probe in input order: the
// position as given, the unit normal, and the irradiance H in W/m^2 (DESIGN.md section 2),
// every number printed with %.9g.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"

namespace radbake {

struct Probe {
    DVec3 position{0.0};  // as written in the file
    DVec3 normal{0.0, 0.0, 1.0};  // unit
    SourceLocation location;  // the line it came from
};

// Every bad line is reported as file:line:col and skipped; the caller checks hasErrors().
std::vector<Probe> parseProbes(std::string_view text, const std::string& file_name, Diagnostics& diagnostics);

// Reads and parses `path`; nullopt after reporting an unreadable file or any bad line.
std::optional<std::vector<Probe>> readProbes(const std::string& path, Diagnostics& diagnostics);

// irradiance[i] belongs to probes[i].
std::string formatProbesCsv(const std::vector<Probe>& probes, const std::vector<DVec3>& irradiance);

bool writeProbesCsv(const std::filesystem::path& path, const std::vector<Probe>& probes,
                    const std::vector<DVec3>& irradiance, Diagnostics& diagnostics);

}  // namespace radbake
