#include "cli/option_checks.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace radbake::cli {
namespace {

// "1e6" rather than "1e+06" or 310 digits: %g with the exponent's sign and zeros dropped.
std::string readable(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    std::string out = text;
    const size_t e = out.find('e');
    if (e == std::string::npos) return out;
    std::string exponent = out.substr(e + 1);
    const bool negative = exponent.front() == '-';
    exponent.erase(0, exponent.find_first_not_of("+-0"));
    return out.substr(0, e + 1) + (negative ? "-" : "") + (exponent.empty() ? "0" : exponent);
}

std::string describeReal(double low, double high, bool low_open) {
    if (std::isinf(high)) return (low_open ? "> " : ">= ") + readable(low);
    return std::string("in ") + (low_open ? "(" : "[") + readable(low) + ", " + readable(high) + "]";
}

// The whole text as a number, read as CLI11 reads it; false for anything else.
bool parseReal(const std::string& text, double& value) {
    if (text.empty()) return false;
    char* end = nullptr;
    const long double parsed = std::strtold(text.c_str(), &end);
    value = static_cast<double>(parsed);
    return end == text.c_str() + text.size();
}

// Plain decimal digits with an optional sign; `overflow` when they exceed a long long.
bool parseWhole(const std::string& text, long long& value, bool& overflow) {
    const size_t start = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
    if (text.size() <= start || text.find_first_not_of("0123456789", start) != std::string::npos) return false;
    errno = 0;
    value = std::strtoll(text.c_str(), nullptr, 10);
    overflow = errno == ERANGE;
    return true;
}

}  // namespace

CLI::Validator realIn(double low, double high, bool low_open) {
    const std::string range = describeReal(low, high, low_open);
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            double value = 0.0;
            if (text.empty()) return "an empty value is not a number " + range;
            if (!parseReal(text, value)) return "'" + text + "' is not a number " + range;
            if (!std::isfinite(value)) return "'" + text + "' is not a finite number " + range;
            if (value < low || (low_open && value == low) || value > high) return "'" + text + "' is not " + range;
            return {};
        },
        range);
}

CLI::Validator wholeIn(long long low, long long high) {
    const std::string range = "in [" + std::to_string(low) + ", " + std::to_string(high) + "]";
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            long long value = 0;
            bool overflow = false;
            if (text.empty()) return "an empty value is not a whole number " + range;
            if (!parseWhole(text, value, overflow)) return "'" + text + "' is not a whole number " + range;
            if (overflow || value < low || value > high) return "'" + text + "' is not " + range;
            text = std::to_string(value);
            return {};
        },
        range);
}

void addSceneScaleOptions(CLI::App& command, ImportOptions& import) {
    // Micrometres to a thousand kilometres per unit: beyond them a float scene loses its shape.
    command.add_option("--unit-scale", import.unit_scale, "Metres per scene unit")
        ->check(realIn(1e-6, 1e6))
        ->capture_default_str();
    command.add_option("--emission-scale", import.emission_scale, "Multiplies every emitted radiance")
        ->check(nonNegativeReal(1e6))
        ->capture_default_str();
}

void addDaylightOptions(CLI::App& command, DaylightOptions& daylight) {
    command
        .add_option_function<std::string>(
            "--sky",
            [&daylight](const std::string& text) {
                daylight.sky = *parseSkyModel(text);
                daylight.sky_map = daylight.sky == SkyModel::Map ? text : std::string();
            },
            "Light the scene by a sky at infinity: uniform (radiance --sky-radiance above the horizon), overcast "
            "(the CIE overcast sky, --sky-radiance at the zenith, a third of it at the horizon; both black below "
            "it), background (the file's VRML97 Background colours times --sky-radiance, over the whole sphere), "
            "FILE.exr (an equirectangular environment map over the whole sphere times --sky-radiance: top row "
            "the zenith, centre column azimuth 0; a sun drawn in it becomes a directional light) or none")
        ->check(CLI::Validator(
            [](std::string& text) {
                return parseSkyModel(text) ? std::string()
                                           : "'" + text + "' is not none, uniform, overcast, background or a .exr file";
            },
            ""))
        ->default_str("none")
        ->type_name("MODEL");
    command.add_option("--sky-radiance", daylight.sky_radiance,
                       "The uniform sky's radiance, the overcast sky's zenith radiance, in W sr^-1 m^-2; "
                       "multiplies a Background's colours and an environment map's radiances")
        ->check(nonNegativeReal(1e9))
        ->capture_default_str();
    command
        .add_option_function<std::string>(
            "--up", [&daylight](const std::string& text) { daylight.up = *parseUpAxis(text); },
            "The axis the sky and the sun are oriented by (the geometry is not moved)")
        ->check(CLI::IsMember({"+x", "-x", "+y", "-y", "+z", "-z"}))
        ->default_str("+y")
        ->type_name("AXIS");
    command
        .add_option_function<std::string>(
            "--sun", [&daylight](const std::string& text) { daylight.sun = parseSunPosition(text); },
            "A sun at AZIMUTH,ELEVATION degrees: elevation above the horizon, azimuth about --up from +x "
            "towards +z for +y (README: every up axis)")
        ->check(CLI::Validator(
            [](std::string& text) {
                return parseSunPosition(text) ? std::string()
                                              : "'" + text + "' is not AZIMUTH,ELEVATION in degrees "
                                                             "(finite, elevation in [-90, 90])";
            },
            ""))
        ->type_name("AZ,EL");
    command
        .add_option("--sun-irradiance", daylight.sun_irradiance, "The sun's irradiance on a plane facing it, W/m^2")
        ->check(nonNegativeReal(1e9))
        ->capture_default_str();
    command.add_option("--sun-diameter", daylight.sun_diameter_degrees,
                       "The sun's angular diameter in degrees (its shadows' penumbrae); 0: hard shadows")
        ->check(realIn(0.0, 90.0))
        ->capture_default_str();
}

void addReadRootOption(CLI::App& command, ImportOptions& import) {
    command
        .add_option("--read-root", import.read_roots,
                    "Also let the scene read files (Inline, EXTERNPROTO, textures, MTL, glTF buffers) under this "
                    "folder; by default only under the scene file's own folder; repeatable")
        ->check(nonEmptyPath())
        ->check(CLI::Validator(CLI::ExistingDirectory).description(""))
        ->allow_extra_args(false)
        ->type_name("DIR");
}

void addMaxMemoryOption(CLI::App& command, double& max_memory_mb) {
    constexpr double kMaxMemoryMb = 1e9;  // MiB: a pebibyte
    command
        .add_option("--max-memory", max_memory_mb,
                    "Memory budget in MiB (0: 3/4 of this machine's memory, or of ulimit -v when lower): "
                    "geometry a scene expands to, each texture and the validation are checked against it "
                    "before they are built, and the solve stops when the process holds more; an error "
                    "instead of a failed allocation or a kill")
        ->check(nonNegativeReal(kMaxMemoryMb))
        ->capture_default_str();
}

void addLightmapLayoutOptions(CLI::App& command, LightmapSettings& lightmaps, std::string& lightmap_scales) {
    // Far above any real use, well below what overflows the texel arithmetic.
    constexpr double kMaxTexelDensity = 1e6;  // texels per scene unit
    constexpr long long kMaxTexels = 1LL << 32;
    command
        .add_option("--texel-density", lightmaps.texels_per_unit,
                    "Lightmap texels per scene unit. Default: 16 per metre (16 / --unit-scale per scene unit), "
                    "raised for a small scene to 34 texels along its largest side")
        ->check(positiveReal(kMaxTexelDensity));
    command.add_option("--atlas-size", lightmaps.atlas_size, "Largest lightmap atlas side, in texels")
        ->transform(wholeIn(16, 16384))
        ->capture_default_str();
    command
        .add_option("--padding", lightmaps.padding,
                    "Texels around every chart, filled by dilation, so bilinear filtering never reads a neighbour")
        ->transform(wholeIn(0, 64))
        ->capture_default_str();
    command
        .add_option("--max-texels", lightmaps.max_texels,
                    "Most lightmap texels (charts, padding excluded) a bake may evaluate; over it the default "
                    "density is lowered with a warning, a given --texel-density is an error")
        ->transform(wholeIn(1, kMaxTexels))
        ->capture_default_str();
    command
        .add_option("--lightmap-scales", lightmap_scales,
                    "Per-object lightmap density: a file of 'NAME SCALE' lines, NAME a mesh or material name, "
                    "SCALE a factor on --texel-density for its meshes (applied within --max-texels)")
        ->check(nonEmptyPath());
}

CLI::Validator nonEmptyPath() {
    return CLI::Validator([](std::string& text) { return text.empty() ? std::string("an empty path is not a file") : ""; },
                          "");
}

}  // namespace radbake::cli
