#include "core/diagnostics.h"

namespace radbake {

std::string formatDiagnostic(const Diagnostic& diagnostic) {
    std::string text;
    if (!diagnostic.location.file.empty()) {
        text += diagnostic.location.file;
        if (diagnostic.location.line > 0) {
            text += ':' + std::to_string(diagnostic.location.line);
            if (diagnostic.location.column > 0) text += ':' + std::to_string(diagnostic.location.column);
        }
        text += ": ";
    }
    switch (diagnostic.severity) {
        case Severity::Note: text += "note: "; break;
        case Severity::Warning: text += "warning: "; break;
        case Severity::Error: text += "error: "; break;
    }
    text += diagnostic.message;
    return text;
}

void Diagnostics::note(const SourceLocation& where, std::string message) {
    report(Severity::Note, where, std::move(message));
}
void Diagnostics::warning(const SourceLocation& where, std::string message) {
    report(Severity::Warning, where, std::move(message));
}
void Diagnostics::error(const SourceLocation& where, std::string message) {
    report(Severity::Error, where, std::move(message));
}

void Diagnostics::report(Severity severity, const SourceLocation& where, std::string message) {
    if (severity == Severity::Error) ++error_count_;
    if (severity == Severity::Warning) ++warning_count_;
    diagnostics_.push_back({severity, where, std::move(message)});
    if (sink) sink(diagnostics_.back());
}

}  // namespace radbake
