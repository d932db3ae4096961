#pragma once
// Diagnostics collects located warnings and errors from every stage. Nothing throws across
// a module boundary: a stage reports here and returns, and the caller checks hasErrors().
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace radbake {

struct SourceLocation {
    std::string file;  // empty when the input has no file (a scene built in code)
    int line = 0;      // 1-based; 0 when unknown
    int column = 0;    // 1-based; 0 when unknown
};

enum class Severity { Note, Warning, Error };

struct Diagnostic {
    Severity severity = Severity::Error;
    SourceLocation location;
    std::string message;
};

// "file:line:col: error: message", leaving out the parts that are unknown.
std::string formatDiagnostic(const Diagnostic& diagnostic);

class Diagnostics {
public:
    // Called for each diagnostic as it is reported (e.g. to print it); may be empty.
    std::function<void(const Diagnostic&)> sink;

    void note(const SourceLocation& where, std::string message);
    void warning(const SourceLocation& where, std::string message);
    void error(const SourceLocation& where, std::string message);

    bool hasErrors() const { return error_count_ > 0; }
    int errorCount() const { return error_count_; }
    int warningCount() const { return warning_count_; }
    const std::vector<Diagnostic>& all() const { return diagnostics_; }

private:
    void report(Severity severity, const SourceLocation& where, std::string message);
    std::vector<Diagnostic> diagnostics_;
    int error_count_ = 0;
    int warning_count_ = 0;
};

}  // namespace radbake
