#pragma once
// 2D samples from a PCG32 stream, in a fixed order of draws.

#include "core/math.h"
#include "core/rng.h"

namespace candela {

// A 2D sample from two draws, the second coordinate drawn first. Written out because C++ leaves
// the order in which a call's arguments are evaluated unspecified: Vec2(rng.next_float(),
// rng.next_float()) gave GCC's builds (last argument first) other images than clang's. Drawing y
// first keeps the images the GCC builds have always made.
inline Vec2 next_vec2(PCG32& rng) {
    const float y = rng.next_float();
    const float x = rng.next_float();
    return Vec2(x, y);
}

}  // namespace candela
