#pragma once
// The film (Mitsuba's `hdrfilm`) and the image blocks that accumulate filtered samples.

#include "core/filter.h"
#include "core/object.h"
#include "core/spectrum.h"

#include <vector>

namespace candela {

class Film : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Film; }
    virtual Vec2i full_size() const = 0;   // width, height of the whole film
    virtual Vec2i crop_offset() const = 0;
    virtual Vec2i crop_size() const = 0;   // the size of the image that is written
    virtual const ReconstructionFilter& filter() const = 0;
    virtual bool float32() const = 0;      // component_format: float32 or float16
};

// A rectangle of the film that accumulates sum(w * L) and sum(w) per pixel, with a border of the
// filter's radius so that samples near the edge can reach neighbouring pixels. Blocks are merged
// into the final image in a fixed order, which keeps renders deterministic.
class ImageBlock {
public:
    ImageBlock() = default;
    // `offset` and `size` are in film pixels (the crop's coordinate system).
    ImageBlock(const Vec2i& offset, const Vec2i& size, const ReconstructionFilter* filter);
    // How many pixels beyond its own a sample reaches with this filter: the farthest pixel centre
    // within the filter radius of a point inside the pixel is ceil(radius - 0.5) pixels away.
    static int reach(const ReconstructionFilter& filter);

    // Splats radiance L at continuous film position `pos` (in pixels, crop coordinates).
    void put(const Vec2& pos, const Spectrum& L);
    // Adds this block into a full-size accumulation buffer (4 floats per pixel).
    void accumulate_into(std::vector<double>& buffer, const Vec2i& buffer_size) const;
    void clear();

    const Vec2i& offset() const { return offset_; }
    const Vec2i& size() const { return size_; }

private:
    Vec2i offset_{0}, size_{0};
    int border_ = 0;
    Vec2i stored_size_{0};
    const ReconstructionFilter* filter_ = nullptr;
    std::vector<float> data_;  // (r, g, b, weight) per stored pixel
};

}  // namespace candela
