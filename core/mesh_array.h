#pragma once
// MeshArray: the vector type of mesh data (positions, normals, uvs, triangles).

#include "core/mapped_file.h"

#include <cstddef>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace candela {

// The allocator of a mesh's arrays: resize() leaves new elements default-initialized (for floats
// and glm vectors, unwritten) instead of value-initialized (zeroed). The readers resize an array
// and then write every element, and zero-filling first was a serial pass over the memory: 0.1-0.2 s
// of the 0.5 s by which loading a 10^7-triangle PLY trailed the floor (bench_scale, 2026-12-04).
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    // Arrays of 4 MB and more on huge pages (allocate_large_array, core/mapped_file.h): the
    // arrays of large meshes, which their readers fill right after allocating them.
    static constexpr size_t LargeBytes = size_t(1) << 22;
    T* allocate(size_t n) {
        if (n > size_t(-1) / sizeof(T)) throw std::bad_alloc();
        if (n * sizeof(T) >= LargeBytes) return static_cast<T*>(allocate_large_array(n * sizeof(T)));
        return std::allocator<T>::allocate(n);
    }
    void deallocate(T* p, size_t n) noexcept {
        if (n * sizeof(T) >= LargeBytes)
            free_large_array(p);
        else
            std::allocator<T>::deallocate(p, n);
    }
};
template <class T>
using MeshArray = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace candela
