#pragma once
// The folders in which a scene's relative file names are looked for, first match wins (Mitsuba 3's
// FileResolver). A scene file starts with its own folder, the working directory and the search
// folders its loader was given (`candela render -a`, as `mitsuba -a`); each <path value="..."/>
// puts its folder in front; an included file puts its own folder in
// front of the including file's list. See core/xml.cpp for the order in full.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace candela {

class FileResolver {
public:
    // Puts a folder first (prepend) or last (append); a folder already in the list moves there.
    void prepend(const std::filesystem::path& folder);
    void append(const std::filesystem::path& folder);

    // The first folder/name that is a regular file (or a directory), or nothing. An absolute
    // name is returned as it is when it exists.
    std::optional<std::filesystem::path> find_file(const std::string& name) const;
    std::optional<std::filesystem::path> find_directory(const std::string& name) const;

    const std::vector<std::filesystem::path>& folders() const { return folders_; }
    // Every file find_file() has returned, in order, shared by all copies of this resolver: the
    // files a scene read besides itself (the farm hashes them to tell renders apart).
    const std::vector<std::filesystem::path>& found_files() const { return *found_files_; }

    // Confines every FileResolver of the process to files inside `folders` (symbolic links and
    // ".." resolved first): any other file is "not found". For programs that load untrusted
    // scenes, such as the fuzzers, so that an <include> or a filename cannot reach /proc, /etc
    // or the user's files. Call once, before loading; an empty list lifts the confinement.
    static void confine_to(const std::vector<std::filesystem::path>& folders);
    // Folders every scene loaded afterwards searches after its own folder and the working
    // directory: `candela render -a`, as `mitsuba -a` appends them to Mitsuba's (thread-wide)
    // FileResolver. Each must be a directory (InputError naming it otherwise); an empty list
    // clears them.
    static void set_search_folders(const std::vector<std::filesystem::path>& folders);
    static const std::vector<std::filesystem::path>& search_folders();
    // "a, b, c": the folders, for error messages.
    std::string describe() const;

private:
    template <typename Test>
    std::optional<std::filesystem::path> find(const std::string& name, Test test) const;
    std::vector<std::filesystem::path> folders_;
    std::shared_ptr<std::vector<std::filesystem::path>> found_files_ = std::make_shared<std::vector<std::filesystem::path>>();
};

}  // namespace candela
