#include "export/probes.h"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "core/regular_file.h"
#include "export/output_transaction.h"

namespace radbake {

namespace {

struct Field {
    std::string_view text;
    int column = 0;  // 1-based
};

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Splits a line into fields; false after reporting a misplaced comma.
bool splitFields(std::string_view line, SourceLocation where, std::vector<Field>& fields,
                 Diagnostics& diagnostics) {
    bool comma_pending = false;  // a comma was read and no field has followed it yet
    size_t i = 0;
    while (true) {
        while (i < line.size() && isBlank(line[i])) ++i;
        if (i == line.size() || line[i] == '#') break;
        if (line[i] == ',') {
            if (fields.empty() || comma_pending) {
                where.column = static_cast<int>(i) + 1;
                diagnostics.error(where, "empty field: expected a number before this comma");
                return false;
            }
            comma_pending = true;
            ++i;
            continue;
        }
        const size_t start = i;
        while (i < line.size() && !isBlank(line[i]) && line[i] != ',' && line[i] != '#') ++i;
        fields.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
        comma_pending = false;
    }
    if (comma_pending) {
        where.column = static_cast<int>(line.find_last_of(',')) + 1;
        diagnostics.error(where, "trailing comma: expected a number after it");
        return false;
    }
    return true;
}

bool parseNumber(const Field& field, double& value) {
    std::string_view text = field.text;
    if (text.size() > 1 && text[0] == '+') text.remove_prefix(1);  // from_chars rejects a leading '+'
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc() && end == text.data() + text.size() && std::isfinite(value);
}

std::string quoted(std::string_view text) {
    constexpr size_t kMax = 40;  // keep messages one line long
    return "'" + std::string(text.substr(0, kMax)) + (text.size() > kMax ? "...'" : "'");
}

}  // namespace

std::vector<Probe> parseProbes(std::string_view text, const std::string& file_name, Diagnostics& diagnostics) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte order mark
    std::vector<Probe> probes;
    int line_number = 0;
    while (!text.empty() || line_number == 0) {
        ++line_number;
        const size_t end = text.find('\n');
        const std::string_view line = text.substr(0, end);
        text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
        const SourceLocation where{file_name, line_number, 0};

        std::vector<Field> fields;
        if (!splitFields(line, where, fields, diagnostics) || fields.empty()) continue;
        if (fields.size() != 6) {
            SourceLocation at = where;
            at.column = fields.size() > 6 ? fields[6].column : fields.front().column;
            diagnostics.error(at, "expected 6 numbers (x y z nx ny nz), found " + std::to_string(fields.size()) +
                                      " fields");
            continue;
        }
        double numbers[6];
        bool ok = true;
        for (int k = 0; k < 6 && ok; ++k) {
            if (!parseNumber(fields[k], numbers[k])) {
                diagnostics.error({file_name, line_number, fields[k].column},
                                  "not a finite number: " + quoted(fields[k].text));
                ok = false;
            }
        }
        if (!ok) continue;
        const DVec3 normal(numbers[3], numbers[4], numbers[5]);
        const double length = glm::length(normal);
        if (!(length > 0.0) || !std::isfinite(length)) {
            diagnostics.error({file_name, line_number, fields[3].column}, "probe normal is zero");
            continue;
        }
        Probe probe;
        probe.position = DVec3(numbers[0], numbers[1], numbers[2]);
        probe.normal = normal / length;
        probe.location = {file_name, line_number, fields[0].column};
        probes.push_back(probe);
    }
    return probes;
}

std::optional<std::vector<Probe>> readProbes(const std::string& path, Diagnostics& diagnostics) {
    // A FIFO would block the bake before it starts, a device never end.
    std::string why;
    const std::optional<std::string> text = readRegularFile(path, why);
    if (!text) {
        diagnostics.error({path, 0, 0}, "cannot open probe file: " + why);
        return std::nullopt;
    }
    const int errors_before = diagnostics.errorCount();
    std::vector<Probe> probes = parseProbes(*text, path, diagnostics);
    if (diagnostics.errorCount() > errors_before) return std::nullopt;
    return probes;
}

std::string formatProbesCsv(const std::vector<Probe>& probes, const std::vector<DVec3>& irradiance) {
    std::string out = "x,y,z,nx,ny,nz,r,g,b\n";
    char line[256];
    for (size_t i = 0; i < probes.size(); ++i) {
        const Probe& p = probes[i];
        const DVec3 h = i < irradiance.size() ? irradiance[i] : DVec3(0.0);
        std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", p.position.x, p.position.y,
                      p.position.z, p.normal.x, p.normal.y, p.normal.z, h.x, h.y, h.z);
        out += line;
    }
    return out;
}

bool writeProbesCsv(const std::filesystem::path& path, const std::vector<Probe>& probes,
                    const std::vector<DVec3>& irradiance, Diagnostics& diagnostics) {
    return writeFileBytes(path, formatProbesCsv(probes, irradiance), diagnostics);
}

}  // namespace radbake
