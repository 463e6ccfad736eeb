#include "core/warning.h"

#include <iostream>
#include <mutex>

namespace candela {

namespace {
std::mutex& sink_mutex() {
    static std::mutex m;
    return m;
}
WarningSink& current_sink() {
    static WarningSink sink;
    return sink;
}
}  // namespace

void warn(const SourceLocation& where, const std::string& message) {
    // Not from a file (an option, a -D): "warning: ...", as errors say "error: ...".
    std::string line = (where.file.empty() ? std::string() : where.str() + ": ") + "warning: " + message;
    std::lock_guard<std::mutex> lock(sink_mutex());
    if (current_sink())
        current_sink()(line);
    else
        std::cerr << line << "\n";
}

WarningSink set_warning_sink(WarningSink sink) {
    std::lock_guard<std::mutex> lock(sink_mutex());
    WarningSink previous = std::move(current_sink());
    current_sink() = std::move(sink);
    return previous;
}

}  // namespace candela
