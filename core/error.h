#pragma once
// Errors that stop a run. A SceneError names the file and line of the offending input; the
// command line prints it as "file:line: message" and exits with code 2.

#include <stdexcept>
#include <string>

namespace candela {

struct SourceLocation {
    std::string file;  // empty when the value did not come from a file (e.g. a -D override)
    int line = 0;

    std::string str() const {
        if (file.empty()) return "<command line>";
        return line > 0 ? file + ":" + std::to_string(line) : file;
    }
};

class SceneError : public std::runtime_error {
public:
    SceneError(const SourceLocation& where, const std::string& message)
        : std::runtime_error(where.str() + ": " + message), location(where), what_(message) {}
    SourceLocation location;
    const std::string& message() const { return what_; }

private:
    std::string what_;
};

// An error in the arguments or the environment that is not tied to a scene file line
// (an unwritable output path, an unreadable image given on the command line).
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A broken internal contract (a bug in Candela, not in the input): the command line prints it as
// "internal error: ..." and exits with code 70 (EX_SOFTWARE) instead of crashing or looping.
class InternalError : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

}  // namespace candela
