#include "core/file_output.h"

#include "core/error.h"
#include "core/image.h"
#include "core/stop.h"

#include <unistd.h>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace candela {

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    check_output_path(path);
    fs::path p(path);
    std::string name = "." + p.stem().string() + ".tmp" + std::to_string(::getpid()) + p.extension().string();
    std::string tmp = (p.has_parent_path() ? p.parent_path() / name : fs::path(name)).string();
    std::error_code ec;
    // Removed by the stop handlers should a signal end the process before the rename.
    const int slot = register_temporary(tmp);
    try {
        write(tmp);
    } catch (const std::exception& e) {
        fs::remove(tmp, ec);
        unregister_temporary(slot);
        throw InputError(path + ": cannot write: " + e.what());
    }
    fs::rename(tmp, path, ec);
    unregister_temporary(slot);
    if (ec) {
        fs::remove(tmp, ec);
        throw InputError(path + ": cannot write: " + ec.message());
    }
}

void write_file_atomically(const std::string& path, const std::string& contents) {
    write_atomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << contents;
        out.close();
        if (!out) throw std::runtime_error("write failed");
    });
}

}  // namespace candela
