#pragma once
// The viewer's frames: a linear image tonemapped to 8-bit sRGB and compressed as JPEG with
// libjpeg-turbo (Debian's libturbojpeg). Measured for the 512 x 512 Cornell box: about 40 KB and
// 3 ms per frame at quality 90, against 3 MB for raw float RGB (docs/viewer.md).

#include "core/image.h"

#include <string>

namespace candela {

enum class JpegTone {
    Srgb,    // 2^exposure times the value, clamped to [0, 1], the sRGB curve
    Filmic,  // 2^exposure times the value through Narkowicz's ACES fit, then the sRGB curve
    Display  // values already for display (a heatmap): clamped only
};

// The JPEG file's bytes of the image's R, G, B.
std::string encode_jpeg(const Image& image, JpegTone tone, float exposure, int quality = 90);

}  // namespace candela
