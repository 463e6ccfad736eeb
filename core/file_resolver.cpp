#include "core/file_resolver.h"

#include "core/error.h"

#include <algorithm>

namespace fs = std::filesystem;

namespace candela {

namespace {
std::vector<fs::path>& confinement() {
    static std::vector<fs::path> folders;
    return folders;
}

std::vector<fs::path>& global_search_folders() {
    static std::vector<fs::path> folders;
    return folders;
}

// Whether `p` lies inside one of the confinement folders (always, without a confinement).
bool allowed(const fs::path& p) {
    if (confinement().empty()) return true;
    std::error_code ec;
    fs::path real = fs::weakly_canonical(p, ec);
    if (ec) return false;
    for (const fs::path& folder : confinement()) {
        auto [f, r] = std::mismatch(folder.begin(), folder.end(), real.begin(), real.end());
        if (f == folder.end()) return true;
    }
    return false;
}
}  // namespace

void FileResolver::confine_to(const std::vector<fs::path>& folders) {
    confinement().clear();
    for (const fs::path& folder : folders) confinement().push_back(fs::canonical(folder));
}

void FileResolver::set_search_folders(const std::vector<fs::path>& folders) {
    std::vector<fs::path> checked;
    for (const fs::path& folder : folders) {
        std::error_code ec;
        if (!fs::is_directory(folder, ec)) throw InputError("search folder \"" + folder.string() + "\" not found");
        checked.push_back(fs::absolute(folder).lexically_normal());
    }
    global_search_folders() = checked;
}

const std::vector<fs::path>& FileResolver::search_folders() { return global_search_folders(); }

void FileResolver::prepend(const fs::path& folder) {
    folders_.erase(std::remove(folders_.begin(), folders_.end(), folder), folders_.end());
    folders_.insert(folders_.begin(), folder);
}

void FileResolver::append(const fs::path& folder) {
    folders_.erase(std::remove(folders_.begin(), folders_.end(), folder), folders_.end());
    folders_.push_back(folder);
}

template <typename Test>
std::optional<fs::path> FileResolver::find(const std::string& name, Test test) const {
    fs::path p(name);
    std::error_code ec;
    if (p.is_absolute()) return test(p, ec) && allowed(p) ? std::optional<fs::path>(p) : std::nullopt;
    for (const fs::path& folder : folders_) {
        fs::path candidate = folder / p;
        if (test(candidate, ec) && allowed(candidate)) return candidate.lexically_normal();
    }
    return std::nullopt;
}

std::optional<fs::path> FileResolver::find_file(const std::string& name) const {
    auto found = find(name, [](const fs::path& p, std::error_code& ec) { return fs::is_regular_file(p, ec); });
    if (found) found_files_->push_back(*found);
    return found;
}

std::optional<fs::path> FileResolver::find_directory(const std::string& name) const {
    return find(name, [](const fs::path& p, std::error_code& ec) { return fs::is_directory(p, ec); });
}

std::string FileResolver::describe() const {
    std::string out;
    for (const fs::path& f : folders_) out += (out.empty() ? "" : ", ") + f.string();
    return out.empty() ? "nowhere" : out;
}

}  // namespace candela
