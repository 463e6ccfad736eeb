#pragma once
// Reading and writing PNG files with libpng itself, as core/exr_input.h reads OpenEXR files: without the image
// module (core/image_codecs.h), whose OpenImageIO and ~250 libraries took about 0.33 s of every
// run that read a PNG texture (2026-12-05: textured.xml's whole start 0.43 s against 0.09 s for the
// Cornell box). PNG is the format of most textures in Mitsuba 3's documentation scenes.
//
// The result is what the module's reader (OpenImageIO 2.4) gives, value for value:
// - libpng's decoding with its expansion (palettes to RGB, tRNS to an alpha channel, 1-, 2- and
//   4-bit grey to 8 bits); 16-bit files stay 16-bit (integer_bits 16), the others 8-bit;
// - channels R, G, B, A, or Y for grey and Y, A for grey with alpha;
// - alpha unassociated, as PNG stores it and Mitsuba's Bitmap reads it (the module is asked for
//   the same: oiio:UnassociatedAlpha, imageio/oiio_codecs.cpp), so that a texture's colour is not
//   darkened where it is transparent;
// - the metadata: oiio:ColorSpace ("sRGB" for an sRGB chunk or none, "linear" or "Gamma<g>" from
//   gAMA, with oiio:Gamma), DateTime (tIME), text chunks (Description, Author and Title under
//   OpenImageIO's names ImageDescription, Artist and DocumentName), ResolutionUnit, XResolution and
//   YResolution (pHYs, per inch when given per metre) and PixelAspectRatio.
// What it cannot reproduce exactly it leaves to the module: ICC profiles, Exif and XMP (which
// OpenImageIO decodes into many attributes), text keys that would collide with another attribute,
// images wider or taller than 65536 pixels or too large to read (the module's messages say why),
// and every file libpng reports an error in (the module's message names it).

#include "core/image_codecs.h"

#include <string>

namespace candela {

// "" when every chunk of the PNG file `path` declares a length that fits in the bytes the file has
// left, else the error. libpng allocates and zeroes a chunk's buffer at its declared length before
// reading it, and so does the module's reader: a 570-byte file whose text chunk declared 2 GB took
// 2.2 GB and 11 s to fail (found by fuzz_image). Both readers run only after this check.
std::string png_chunk_problem(const std::string& path);

// Reads `path` (its pixels too when `pixels`) into `out` and returns true; returns false, with
// `out` untouched, for what it leaves to the image module (above).
bool read_png(const std::string& path, bool pixels, DecodedImage& out);

// The bytes of an 8-bit PNG file of width x height pixels of 1 to 4 channels (grey, grey and
// alpha, RGB, RGBA), interleaved: display-referred values, tagged sRGB. Written by libpng at its
// default compression; writing one loaded the image module (0.38 s of a render with --png, and
// of a notebook's first picture) until 2026-12-05. Throws InputError when libpng refuses.
std::string png_file_bytes(int width, int height, int channels, const unsigned char* samples);

}  // namespace candela
