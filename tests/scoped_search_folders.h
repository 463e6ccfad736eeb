#pragma once
// FileResolver's search folders (candela render -a) for one scope; cleared at its end.

#include "core/file_resolver.h"

namespace candela::test {

struct ScopedSearchFolders {
    explicit ScopedSearchFolders(const std::vector<std::filesystem::path>& folders) { FileResolver::set_search_folders(folders); }
    ~ScopedSearchFolders() { FileResolver::set_search_folders({}); }
    ScopedSearchFolders(const ScopedSearchFolders&) = delete;
    ScopedSearchFolders& operator=(const ScopedSearchFolders&) = delete;
};

}  // namespace candela::test
