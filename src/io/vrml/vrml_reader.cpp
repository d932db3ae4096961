// Entry points of the VRML readers: file loading (gzip included), URL resolution and the
// dispatch between VRML97 and VRML 1.0. The only file that includes zlib.
#include "io/vrml/vrml_reader.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "core/regular_file.h"
#include "io/vrml/vrml1_reader.h"
#include "io/vrml/vrml97_builder.h"

namespace radbake {
namespace {

namespace fs = std::filesystem;

bool isGzip(std::string_view bytes) {
    return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
           static_cast<unsigned char>(bytes[1]) == 0x8b;
}

// Gunzips every member of a gzip stream; false with a reason on corrupt data, or on more than
// `max_bytes` of text (a small bomb must not exhaust memory).
bool gunzip(std::string_view bytes, size_t max_bytes, std::string& out, std::string& reason) {
    z_stream z{};
    if (inflateInit2(&z, 15 + 32) != Z_OK) {
        reason = "cannot initialise zlib";
        return false;
    }
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    size_t remaining = bytes.size();
    out.clear();
    std::string chunk(size_t(1) << 18, '\0');
    int status = Z_OK;
    for (;;) {
        if (z.avail_in == 0) {
            const size_t take = std::min<size_t>(remaining, 1u << 30);
            z.avail_in = static_cast<uInt>(take);
            remaining -= take;
        }
        z.next_out = reinterpret_cast<Bytef*>(chunk.data());
        z.avail_out = static_cast<uInt>(chunk.size());
        status = inflate(&z, Z_NO_FLUSH);
        out.append(chunk.data(), chunk.size() - z.avail_out);
        if (out.size() > max_bytes) {
            reason = "decompressed data " + largerThan(max_bytes);
            break;
        }
        if (status == Z_STREAM_END) {
            // Another gzip member may follow (concatenated .gz files).
            if (z.avail_in == 0 && remaining == 0) break;
            if (z.avail_in >= 2 && z.next_in[0] == 0x1f && z.next_in[1] == 0x8b) {
                inflateReset(&z);
                continue;
            }
            break;  // trailing garbage after the stream: ignore it, as gzip does
        }
        if (status != Z_OK) {
            reason = status == Z_BUF_ERROR ? "gzip data is truncated"
                                           : std::string("corrupt gzip data (") + (z.msg ? z.msg : "zlib error") + ")";
            break;
        }
        if (z.avail_in == 0 && remaining == 0 && z.avail_out != 0) {
            reason = "gzip data is truncated";
            break;
        }
    }
    inflateEnd(&z);
    return reason.empty();
}

bool hasScheme(const std::string& url) {
    // "http:", "urn:", "ftp:" ...; a single letter before ':' is a Windows drive.
    const size_t colon = url.find(':');
    if (colon == std::string::npos || colon < 2) return false;
    return std::all_of(url.begin(), url.begin() + static_cast<std::ptrdiff_t>(colon), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
    });
}

std::string percentDecode(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
            out.push_back(static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16)));
            i += 2;
        } else {
            out.push_back(s[i]);
        }
    }
    return out;
}

bool iequals(const std::string& a, const std::string& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

// Walks `relative` from `base` one component at a time, taking a case-insensitive match
// where the exact name does not exist. Returns the plain join when nothing matches.
fs::path caseInsensitiveResolve(const fs::path& base, const fs::path& relative) {
    fs::path current = base;
    std::error_code ec;
    for (const fs::path& part : relative) {
        const fs::path exact = current / part;
        if (part == "." || part == ".." || fs::exists(exact, ec)) {
            current = exact;
            continue;
        }
        fs::path found;
        for (fs::directory_iterator it(current.empty() ? fs::path(".") : current, ec), end; !ec && it != end;
             it.increment(ec)) {
            if (iequals(it->path().filename().string(), part.string())) {
                found = current / it->path().filename();
                break;
            }
        }
        if (found.empty()) return base / relative;
        current = found;
    }
    return current;
}

}  // namespace

bool looksLikeVrml(std::string_view first_bytes) {
    if (first_bytes.starts_with("\xEF\xBB\xBF")) first_bytes.remove_prefix(3);
    // X3D classic encoding ("#X3D V3.x utf8") is read as VRML97.
    return first_bytes.starts_with("#VRML") || first_bytes.starts_with("#X3D") || isGzip(first_bytes);
}

namespace {

// A scope that holds every mesh is no limit (the usual DirectionalLight at the top of a
// file); a light whose scope holds no mesh is reported, since it lights nothing.
void finishLightScopes(Scene& scene, size_t first_light, Diagnostics& diagnostics) {
    for (size_t i = first_light; i < scene.lights.size(); ++i) {
        Light& light = scene.lights[i];
        if (!light.scoped) continue;
        if (light.scope.size() == scene.meshes.size()) {
            light.scoped = false;
            light.scope.clear();
        } else if (light.scope.empty() && light.on) {
            diagnostics.warning(light.location, "this light lights no shape: a VRML97 DirectionalLight lights only "
                                                "its grouping node's children, a VRML 1.0 light only what follows it "
                                                "in its Separator");
        }
    }
}

}  // namespace

bool readVrml(const std::string& path, const VrmlOptions& given, Scene& scene, Diagnostics& diagnostics) {
    VrmlOptions options = given;
    ReadPolicy scene_folder;
    if (!options.policy) {
        scene_folder = readPolicyFor(path, {});
        options.policy = &scene_folder;
    }
    try {
        const std::optional<std::string> text = vrml::loadText(path, {path, 0, 0}, options, diagnostics);
        if (!text) return false;
        std::error_code ec;
        std::vector<std::string> inline_stack{fs::weakly_canonical(path, ec).string()};
        const size_t first_light = scene.lights.size();
        const bool ok = vrml::readText(*text, path, options, inline_stack, scene, diagnostics);
        finishLightScopes(scene, first_light, diagnostics);
        return ok;
    } catch (const std::bad_alloc&) {
        diagnostics.error({path, 0, 0}, "out of memory while reading the scene");
    } catch (const std::exception& e) {
        diagnostics.error({path, 0, 0}, std::string("internal error while reading the scene: ") + e.what());
    }
    return false;
}

namespace vrml {

std::optional<std::string> loadText(const std::string& path, const SourceLocation& from, const VrmlOptions& options,
                                    Diagnostics& diagnostics) {
    // Only a regular file: an Inline naming a FIFO must not block the import.
    const size_t max_bytes = options.policy ? options.policy->max_bytes : kDefaultMaxInputBytes;
    std::string why;
    std::optional<std::string> read = readRegularFile(path, why, max_bytes, openedCheckOf(options.policy));
    if (!read) {
        diagnostics.error(from, "cannot read '" + path + "': " + why);
        return std::nullopt;
    }
    if (options.files_read) options.files_read->push_back(path);
    if (!isGzip(*read)) return read;
    std::string text, reason;
    if (!gunzip(*read, max_bytes, text, reason)) {
        diagnostics.error(from, "'" + path + "': " + reason);
        return std::nullopt;
    }
    return text;
}

bool mayRead(const std::string& path, const SourceLocation& from, const std::string& what, const VrmlOptions& options,
             Diagnostics& diagnostics) {
    if (!options.policy) return true;
    const std::string why = options.policy->whyRefused(path);
    if (why.empty()) return true;
    // Not a regular file, but in the tree: replacing it with one is an edit that rebuilds.
    if (options.policy->whyOutside(path).empty()) noteMissing(path, options);
    if (options.files_refused) options.files_refused->push_back(path);
    diagnostics.warning(from, what + " '" + path + "' refused: " + why + "; skipped");
    return false;
}

void noteMissing(const std::string& path, const VrmlOptions& options) {
    if (options.files_read) options.files_read->push_back(path);
}

std::optional<std::string> resolveUrl(const std::string& base_file, const std::string& url_in) {
    std::string url = url_in;
    if (url.starts_with("file://")) {
        url = url.substr(7);
        if (url.starts_with("localhost/")) url = url.substr(9);
    } else if (url.starts_with("file:")) {
        url = url.substr(5);
    } else if (hasScheme(url)) {
        return std::nullopt;
    }
    if (const size_t cut = url.find_first_of("#?"); cut != std::string::npos) url.resize(cut);
    url = percentDecode(url);
    std::replace(url.begin(), url.end(), '\\', '/');
    if (url.empty()) return std::nullopt;
    const fs::path target(url);
    std::error_code ec;
    if (target.is_absolute()) {
        if (fs::exists(target, ec)) return target.string();
        return caseInsensitiveResolve(target.root_path(), target.relative_path()).string();
    }
    const fs::path base = fs::path(base_file).parent_path();
    const fs::path joined = base / target;
    if (fs::exists(joined, ec)) return joined.lexically_normal().string();
    return caseInsensitiveResolve(base, target).lexically_normal().string();
}

void scopeLight(Light& light, size_t first_mesh, size_t end_mesh) {
    light.scoped = true;
    light.scope.clear();
    for (size_t m = first_mesh; m < end_mesh; ++m) light.scope.push_back(static_cast<uint32_t>(m));
}

bool isVrml97Text(std::string_view text) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
    return text.starts_with("#VRML V2.0") || text.starts_with("#X3D V3") || text.starts_with("#X3D V4");
}

bool readText(std::string_view text, const std::string& path, const VrmlOptions& options,
              std::vector<std::string>& inline_stack, Scene& scene, Diagnostics& diagnostics) {
    std::string_view head = text;
    if (head.starts_with("\xEF\xBB\xBF")) head.remove_prefix(3);
    try {
        // X3D classic encoding (.x3dv, V3.x and V4.x) is VRML97 syntax with a few more statements.
        if (isVrml97Text(head))
            return readVrml97(text, path, options, inline_stack, scene, diagnostics);
        if (head.starts_with("#VRML V1.0")) return readVrml1(text, path, options, inline_stack, scene, diagnostics);
    } catch (const std::bad_alloc&) {
        diagnostics.error({path, 0, 0}, "out of memory while reading the scene");
        return false;
    } catch (const std::exception& e) {
        diagnostics.error({path, 0, 0}, std::string("internal error while reading the scene: ") + e.what());
        return false;
    }
    // The header is quoted only when it is a VRML or X3D one (an unsupported version): any
    // other file's first line may be something secret an Inline pointed at.
    std::string found = "no VRML header";
    if (head.starts_with("#VRML") || head.starts_with("#X3D")) {
        std::string first_line(head.substr(0, std::min<size_t>(head.find_first_of("\r\n"), 40)));
        for (char& c : first_line)
            if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
        found = "found \"" + first_line + "\"";
    }
    diagnostics.error({path, 1, 1}, "not a VRML file: the first line must start with \"#VRML V2.0\" or \"#VRML V1.0\" (" +
                                        found + ")");
    return false;
}

}  // namespace vrml
}  // namespace radbake
