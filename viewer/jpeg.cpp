#include "viewer/jpeg.h"

#include "core/error.h"

#include <turbojpeg.h>

#include <cmath>
#include <memory>
#include <vector>

namespace candela {

namespace {

float srgb_encode(float x) { return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f; }

// The sRGB curve as 8-bit codes over [0, 1] in 4096 steps: pow() per channel took most of a
// frame's encoding time. The step (1/4095) is finer than the curve's slope needs above the
// darkest codes, where the linear segment's 12.92 x makes one step at most 0.8 of a code.
const std::vector<uint8_t>& srgb_table() {
    static const std::vector<uint8_t> table = [] {
        std::vector<uint8_t> t(4096);
        for (size_t i = 0; i < t.size(); ++i) t[i] = uint8_t(std::lround(srgb_encode(float(i) / 4095.0f) * 255.0f));
        return t;
    }();
    return table;
}
uint8_t srgb_byte(float x) { return srgb_table()[size_t(std::clamp(x, 0.0f, 1.0f) * 4095.0f + 0.5f)]; }

// Narkowicz 2015, "ACES Filmic Tone Mapping Curve": a rational fit of the ACES reference
// rendering transform on linear values.
float aces_fit(float x) { return (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f); }

uint8_t to_byte(float v) {
    if (!(v > 0.0f)) return 0;
    if (v >= 1.0f) return 255;
    return uint8_t(std::lround(v * 255.0f));
}

}  // namespace

std::string encode_jpeg(const Image& image, JpegTone tone, float exposure, int quality) {
    const int w = image.width(), h = image.height(), channels = image.channel_count();
    if (w <= 0 || h <= 0) throw InputError("no image to encode");
    const float scale = std::exp2(exposure);
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                float v = image.at(x, y, channels >= 3 ? c : 0);
                if (!std::isfinite(v)) v = 0.0f;
                uint8_t byte;
                if (tone == JpegTone::Srgb)
                    byte = srgb_byte(v * scale);
                else if (tone == JpegTone::Filmic)
                    byte = srgb_byte(aces_fit(std::max(v * scale, 0.0f)));
                else
                    byte = to_byte(v);
                rgb[(size_t(y) * w + x) * 3 + c] = byte;
            }
    std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitCompress(), tjDestroy);
    if (!handle) throw InputError("cannot start the JPEG encoder");
    unsigned char* out = nullptr;
    unsigned long size = 0;
    if (tjCompress2(handle.get(), rgb.data(), w, 0, h, TJPF_RGB, &out, &size, TJSAMP_420, quality, TJFLAG_FASTDCT) != 0) {
        if (out) tjFree(out);
        throw InputError(std::string("JPEG encoding failed: ") + tjGetErrorStr2(handle.get()));
    }
    std::string bytes(reinterpret_cast<const char*>(out), size);
    tjFree(out);
    return bytes;
}

}  // namespace candela
