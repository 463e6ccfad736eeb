#pragma once
// MeshArray: the vector type of mesh data (positions, normals, uvs, triangles).

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
};
template <class T>
using MeshArray = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace candela
