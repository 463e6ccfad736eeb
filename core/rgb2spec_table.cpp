// The coefficient table of core/rgb2spec.h compiled into the program: srgb_sigmoid_table() and
// rgb_to_reflectance_spectrum(). Kept apart from the lookup (core/rgb2spec.cpp) because the table's
// generator, core/data/gen_srgb_sigmoid.cpp, is built from the lookup and must not need its own
// output.

#include "core/rgb2spec.h"

#include "core/byte_order.h"
#include "core/embedded_file.h"
#include "core/error.h"

#include <cstdint>
#include <cstring>
#include <string>

// The table file, compiled in (core/embedded_file.h). CMakeLists.txt generates it in the build
// directory when it configures, and defines its path and MD5. File format (little-endian): "CSG1", uint32 resolution,
// float32 scale[resolution], float32 coefficients[3 * resolution^3 * 3] (core/rgb2spec.h,
// SigmoidTable).
#if !defined(CANDELA_SRGB_SIGMOID_TABLE) || !defined(CANDELA_SRGB_SIGMOID_MD5)
#error "CMakeLists.txt defines CANDELA_SRGB_SIGMOID_TABLE and CANDELA_SRGB_SIGMOID_MD5, the generated table's path and MD5"
#endif

CANDELA_EMBED_FILE(candela_srgb_sigmoid, CANDELA_SRGB_SIGMOID_TABLE);
CANDELA_EMBEDDED_FILE_SYMBOLS(candela_srgb_sigmoid)

namespace candela {

namespace {

SigmoidTable load_embedded_table() {
    static_assert(sizeof(float) == 4 && sizeof(uint32_t) == 4, "the table is float32");
    const unsigned char* data = candela_srgb_sigmoid_begin;
    size_t size = size_t(candela_srgb_sigmoid_end - candela_srgb_sigmoid_begin);
    uint32_t resolution = 0;
    if (size >= 8) std::memcpy(&resolution, data + 4, 4);
    size_t expected = 8 + 4 * size_t(resolution) + 4 * 9 * size_t(resolution) * resolution * resolution;
    if (size < 8 || std::memcmp(data, "CSG1", 4) != 0 || resolution < 2 || resolution > 1024 || size != expected)
        throw InternalError("the compiled-in RGB-to-spectrum table (" CANDELA_SRGB_SIGMOID_TABLE ") is malformed (" + std::to_string(size) +
                            " bytes)");
    // The section is 16-byte aligned and the floats start at byte 8: aligned for float.
    SigmoidTable table;
    table.resolution = int(resolution);
    table.scale = reinterpret_cast<const float*>(data + 8);
    table.coefficients = table.scale + resolution;
    return table;
}

}  // namespace

const SigmoidTable& srgb_sigmoid_table() {
    static const SigmoidTable table = load_embedded_table();
    return table;
}

SigmoidPolynomial rgb_to_reflectance_spectrum(const Vec3& rgb) { return fetch_sigmoid_polynomial(srgb_sigmoid_table(), rgb); }

}  // namespace candela
