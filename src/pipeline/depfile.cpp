#include "pipeline/depfile.h"

#include <system_error>

#include "export/output_transaction.h"

namespace radbake {
namespace {

// Make's escapes: a space or '#' takes a backslash, '$' doubles. (A backslash before a space
// is how gcc writes it, and Ninja's depfile parser reads the same.)
std::string escaped(const std::string& path) {
    std::string out;
    for (const char c : path) {
        if (c == ' ' || c == '#') out += '\\';
        if (c == '$') out += '$';
        out += c;
    }
    return out;
}

}  // namespace

std::string formatDepfile(const std::vector<std::string>& targets, const std::vector<std::string>& inputs) {
    std::string out;
    for (const std::string& target : targets) out += (out.empty() ? "" : " ") + escaped(target);
    out += ":";
    for (const std::string& input : inputs) out += " \\\n " + escaped(input);
    return out + "\n";
}

bool writeDepfile(const std::filesystem::path& path, const std::vector<std::string>& targets,
                  const std::vector<std::string>& inputs, Diagnostics& diagnostics) {
    std::filesystem::path temporary = path;
    temporary += ".radbake-tmp";
    if (!writeFileBytes(temporary, formatDepfile(targets, inputs), diagnostics)) return false;
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        std::filesystem::remove(temporary, ec);
        diagnostics.error({path.string(), 0, 0}, "cannot write the depfile: " + ec.message());
        return false;
    }
    return true;
}

}  // namespace radbake
