#include "pipeline/depfile.h"

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
    const std::string why = replaceRegularFile(path, formatDepfile(targets, inputs));
    if (why.empty()) return true;
    diagnostics.error({path.string(), 0, 0}, "cannot write the depfile: " + why);
    return false;
}

}  // namespace radbake
