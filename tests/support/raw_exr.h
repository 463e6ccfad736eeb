#pragma once
// Writing an image to OpenEXR exactly as it is, NaN and infinity included: what a damaged or
// crafted file holds, which candela's own write_exr (core/image.h) never writes. For the tests
// and the fuzz targets that check how such files are refused.

#include "core/image.h"

#include <string>

namespace candela {

// Every channel as float32, ZIP-compressed, the metadata as string attributes.
void write_exr_as_is(const Image& image, const std::string& path);

}  // namespace candela
