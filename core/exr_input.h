#pragma once
// Reading OpenEXR files with OpenEXR itself, which every Candela program links to write them.
// Reading them through the image module (core/image_codecs.h) loaded OpenImageIO's ~250 libraries
// into every run that read an EXR: about 0.45 s of a 2-core machine (2026-12-05), a fifth of a
// 64-spp render of an environment-lit scene and three times Mitsuba 3's whole start. Environment
// maps and references are EXR files; the module is now loaded for the other formats only.
//
// The result is what the module's reader gave: the data window's pixels as 32-bit floats, the
// channels in OpenImageIO's order (below), integer_bits 0. The metadata holds the header's
// string, int, float and double attributes under their OpenEXR names (as Mitsuba 3's Bitmap
// reads them), other than the required ones (channels, compression, dataWindow, displayWindow,
// lineOrder, pixelAspectRatio, screenWindowCenter, screenWindowWidth).

#include "core/image_codecs.h"

#include <string>
#include <vector>

namespace candela {

// "" when the file's header(s) are safe to hand to OpenEXR, else the error:
// - every attribute declares a size that fits in the bytes the file has left: OpenEXR 3.1
//   allocates and zeroes an attribute's value at its declared size before reading it, so a
//   2.6 kB file declaring a 1.8 GB string took 2.2 GB and 15 s (fuzz_part);
// - every attribute of a standard type holds exactly its declared size: OpenEXR reads such a value
//   by its own length and goes on from there, so a disagreeing size would let it read the rest of
//   the header out of step with the check above;
// - the data window's blocks pass image_size_problem (core/image_codecs.h): OpenEXR allocates its
//   line or tile buffers when it opens the file.
// What OpenEXR itself rejects (names without their terminator, unknown versions) is left to it.
// A multi-part file's headers follow one another up to an empty one.
std::string exr_header_problem(const std::string& path);

// The order OpenImageIO 2.4 gives an EXR's channels, which Candela's readers have always
// returned: grouped by layer (the name up to its last dot; the unnamed layer first, then by name),
// and within a layer the names it knows first, case-insensitively, in the order R, Red, G, Green,
// B, Blue, Y, real, imag, A, Alpha, AR, RA, AG, GA, AB, BA, Z, Depth, Zback; or, in a layer with X
// and Y or Z (positions, normals), R, Red, G, Green, B, Blue, X, Y, Z, real, imag, A, Alpha, AR,
// RA, AG, GA, AB, BA, Depth, Zback; then the others by name. Returns indices into `names`.
std::vector<int> exr_channel_order(const std::vector<std::string>& names);

// Reads `path` (its pixels too when `pixels`) with `threads` OpenEXR threads (0: the calling
// thread). Returns false, with `out` untouched, for what it leaves to the image module:
// multi-part and deep files, subsampled channels, 32-bit unsigned channels (which OpenImageIO
// scales to [0, 1]). Else true, with `error` "" or the whole message
// (the path included); exr_header_problem must have passed.
bool read_exr(const std::string& path, bool pixels, int threads, DecodedImage& out, std::string& error);

}  // namespace candela
