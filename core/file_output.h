#pragma once
// Writing files whole or not at all: write to a temporary beside the target (same extension, so
// format detection still works), then rename it into place; on failure remove the temporary.

#include <functional>
#include <string>

namespace candela {

// Calls write(temporary_path); if it throws, the temporary is removed and the error rethrown as
// InputError naming `path`. check_output_path(path) runs first.
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& write);
// Convenience for text and byte contents.
void write_file_atomically(const std::string& path, const std::string& contents);

}  // namespace candela
