#pragma once
// Warnings: input that Candela accepts but renders differently from what the user may expect
// (a sampler that falls back to another, a colour clamped into gamut). One line each on stderr,
// "file:line: warning: message", so that they read like the errors.

#include "core/error.h"

#include <functional>
#include <string>

namespace candela {

void warn(const SourceLocation& where, const std::string& message);

// Where warnings go (stderr by default). Tests install a sink to check them; returns the
// previous sink. An empty function restores stderr.
using WarningSink = std::function<void(const std::string& line)>;
WarningSink set_warning_sink(WarningSink sink);

}  // namespace candela
