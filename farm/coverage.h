#pragma once
// Which samples of which pixels a part of a split render holds: boxes (CoverageBox, in
// core/pixel_sums.h) of image rectangle x range of sample indices. The parts of one render must
// not overlap, and together they must cover the whole image times [0, spp).

#include "core/integrator.h"

#include <string>
#include <vector>

namespace candela {

// "x,y,w,h@s0:s1" boxes joined by ';' (the candela.coverage metadata of a part).
std::string format_coverage(const std::vector<CoverageBox>& boxes);
std::vector<CoverageBox> parse_coverage(const std::string& text);  // InputError when malformed

// "x,y,w,h" (--crop) and "s0:s1" (--samples); InputError when malformed or empty.
ImageRect parse_rect(const std::string& text);
SampleRange parse_sample_range(const std::string& text);
std::string format_rect(const ImageRect& rect);
std::string format_sample_range(const SampleRange& samples);

bool overlap(const CoverageBox& a, const CoverageBox& b);
// The boxes with those of one rectangle and adjacent sample ranges joined (metadata stays short).
std::vector<CoverageBox> coalesce(std::vector<CoverageBox> boxes);
// The part of `target` (pixels x samples) that `covered` leaves out, as a few large boxes.
std::vector<CoverageBox> uncovered(const std::vector<CoverageBox>& covered, const CoverageBox& target);
// The whole render: every pixel of the image, samples [0, spp).
CoverageBox whole_render(const Vec2i& image, int spp);
// For messages: "samples 4:8" when the box spans the whole image, else "samples 4:8 of pixels
// x,y,w,h".
std::string describe(const CoverageBox& box, const Vec2i& image);

}  // namespace candela
