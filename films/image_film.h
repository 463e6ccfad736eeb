#pragma once
// What Mitsuba 3's image films (hdrfilm, specfilm) read alike: the film's size and crop window,
// the component format, sample_border and the reconstruction filter. Each film adds its channels.
//
// Parameters (Mitsuba 3 names and defaults):
//   width, height         integer   film size in pixels (768 x 576)
//   crop_offset_x/_y      integer   top-left corner of the rendered window (0, 0)
//   crop_width/_height    integer   size of the rendered window (the whole film)
//   component_format      string    float16 (default) or float32; uint32 is refused
//   sample_border         boolean   also sample the pixels just outside the crop window that
//                                   the filter reaches (default false; high_quality_edges is
//                                   Mitsuba 2's name for it)
//   banner                boolean   accepted and ignored, as in Mitsuba 3
//   rfilter               nested    reconstruction filter (default: gaussian)

#include "core/film.h"
#include "core/properties.h"

namespace candela {

class ImageFilm : public Film {
public:
    explicit ImageFilm(const Properties& props);

    Vec2i full_size() const override { return size_; }
    Vec2i crop_offset() const override { return crop_offset_; }
    Vec2i crop_size() const override { return crop_size_; }
    const ReconstructionFilter& filter() const override { return *filter_; }
    bool float32() const override { return float32_; }
    bool sample_border() const override { return sample_border_; }
    SourceLocation location() const override { return location_; }

private:
    SourceLocation location_;
    Vec2i size_, crop_offset_, crop_size_;
    bool float32_ = false, sample_border_ = false;
    Ref<ReconstructionFilter> filter_;
};

}  // namespace candela
