#pragma once
// A file mapped read-only into memory: its bytes are the page cache's pages, not a copy. The mesh
// readers take large files this way, so that a mesh is not held twice (file buffer and arrays).

#include <cstddef>
#include <stdexcept>
#include <string>

namespace candela {

// Asks the kernel to map the pages of [data, data + bytes) now (Linux's MADV_POPULATE_WRITE, or
// _READ for a file mapping), as a first write or read would one page fault at a time. For a loop
// that must run on one thread, such as inflating one zlib stream into fresh arrays, populating
// them from another thread at the same time takes the kernel's page clearing off the loop. Only
// whole pages inside the range are populated; without kernel support (before Linux 5.14) it does
// nothing, and the pages fault in when first touched, as without it.
void populate_pages(const void* data, size_t bytes, bool for_writing);
// The same over all threads (core/parallel.h), for a loop that runs in parallel anyway: on this
// project's virtual machines a page fault costs about as much as populating ten pages, and a
// reader populating the 180 MB of a 10^7-triangle PLY's arrays and the file's pages this way
// first parsed it in 0.55 s against 0.68 s.
void populate_pages_in_parallel(const void* data, size_t bytes, bool for_writing);

// Memory for a large array (mesh data: MeshArray) on transparent huge pages where Linux offers
// them (MADV_HUGEPAGE; the system's default, "madvise", gives them only to memory that asks, as
// Embree's allocations do): aligned to 2 MB, so that one page fault maps 2 MB instead of 4 kB. On
// this project's virtual machines the first write to fresh 4 kB pages ran at about 0.3 GB/s,
// populated or not; to 2 MB pages, populated, 60 MB took 3-11 ms against 120-290 ms. Throws
// std::bad_alloc. Freed with free_large_array().
void* allocate_large_array(size_t bytes);
void free_large_array(void* p);

// Opens a regular file read-only (close-on-exec) and gives its descriptor and size; throws
// std::runtime_error saying what failed ("cannot open it: ...", "not a regular file"), for the
// caller to name the file. MappedFile opens with it; the scene hash reads through it.
int open_regular_file(const std::string& path, size_t& size);

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
