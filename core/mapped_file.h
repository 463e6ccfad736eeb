#pragma once
// A file mapped read-only into memory: its bytes are the page cache's pages, not a copy. The mesh
// readers take large files this way, so that a mesh is not held twice (file buffer and arrays).

#include <cstddef>
#include <stdexcept>
#include <string>

namespace candela {

class MappedFile {
public:
    // Throws std::runtime_error saying what failed ("cannot open it: ...", "not a regular file",
    // "cannot map it: ..."); the caller names the file.
    explicit MappedFile(const std::string& path);
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    const unsigned char* data() const { return data_; }
    size_t size() const { return size_; }

private:
    const unsigned char* data_ = nullptr;
    size_t size_ = 0;
};

}  // namespace candela
