#include "core/mapped_file.h"

#include "core/parallel.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>

namespace candela {

void populate_pages(const void* data, size_t bytes, bool for_writing) {
#if defined(MADV_POPULATE_WRITE) && defined(MADV_POPULATE_READ)
    const uintptr_t page = uintptr_t(::sysconf(_SC_PAGESIZE));
    const uintptr_t begin = (uintptr_t(data) + page - 1) / page * page, end = (uintptr_t(data) + bytes) / page * page;
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, for_writing ? MADV_POPULATE_WRITE : MADV_POPULATE_READ);
#else
    (void)data, (void)bytes, (void)for_writing;
#endif
}

void* allocate_large_array(size_t bytes) {
    constexpr size_t HugePage = size_t(1) << 21;
    const size_t rounded = (bytes + HugePage - 1) / HugePage * HugePage;
    if (rounded < bytes) throw std::bad_alloc();
    void* p = std::aligned_alloc(HugePage, rounded);
    if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
    ::madvise(p, rounded, MADV_HUGEPAGE);  // advice only: without it, 4 kB pages
#endif
    return p;
}

void free_large_array(void* p) { std::free(p); }

void populate_pages_in_parallel(const void* data, size_t bytes, bool for_writing) {
    // Chunks of 2 MB at absolute 2 MB boundaries, so that every page inside the range lies in
    // exactly one chunk.
    constexpr uintptr_t Chunk = uintptr_t(1) << 21;
    if (bytes == 0) return;
    const uintptr_t begin = uintptr_t(data), end = begin + bytes, first = begin / Chunk * Chunk;
    parallel_chunks((end - first + Chunk - 1) / Chunk, 1, [&](size_t from, size_t to) {
        const uintptr_t a = std::max(begin, first + from * Chunk), b = std::min(end, first + to * Chunk);
        if (b > a) populate_pages(reinterpret_cast<const void*>(a), b - a, for_writing);
    });
}

int open_regular_file(const std::string& path, size_t& size) {
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(std::string("cannot open it: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        throw std::runtime_error("not a regular file");
    }
    size = size_t(st.st_size);
    return fd;
}

MappedFile::MappedFile(const std::string& path) {
    const int fd = open_regular_file(path, size_);
    if (size_ > 0) {
        void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
        if (p == MAP_FAILED) {
            int error = errno;
            ::close(fd);
            throw std::runtime_error(std::string("cannot map it: ") + std::strerror(error));
        }
        data_ = static_cast<const unsigned char*>(p);
    }
    ::close(fd);
}

MappedFile::~MappedFile() {
    if (data_) ::munmap(const_cast<unsigned char*>(data_), size_);
}

}  // namespace candela
