#pragma once
// Byte order. Candela's binary inputs (Mitsuba's serialized meshes, tensor files, EXR headers,
// 16-bit PNG samples, the compiled-in RGB-to-spectrum table) are little-endian, and so is every
// machine Candela builds for: the check is made here, once, at compile time, so that readers may
// copy little-endian arrays as they are and no reader keeps a run-time probe or a byte-swapping
// path that no build can reach. (PLY files say their own byte order; their reader swaps the
// big-endian ones.)

#include <cstddef>
#include <cstdint>

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "Candela builds for little-endian machines: its readers copy little-endian data as it is");

namespace candela {

// The unsigned integer stored little-endian in the `bytes` bytes at p (at most 8). Byte by byte,
// so p needs no alignment.
inline uint64_t read_little_endian(const unsigned char* p, size_t bytes) {
    uint64_t value = 0;
    for (size_t i = 0; i < bytes; ++i) value |= uint64_t(p[i]) << (8 * i);
    return value;
}

}  // namespace candela
