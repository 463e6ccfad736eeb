#pragma once
// Reconstruction filters (Mitsuba's `rfilter`): separable, evaluated per axis. eval() is
// normalised so that its 1D integral over [-radius, radius] is 1; the film divides by the sum of
// weights anyway, so normalisation matters only to users of the filter as a density.

#include "core/object.h"

namespace candela {

class ReconstructionFilter : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Filter; }
    float radius() const { return radius_; }
    // 1D weight at offset x (pixels) from the pixel centre; 0 outside the radius.
    virtual float eval(float x) const = 0;

protected:
    float radius_ = 0.5f;
};

}  // namespace candela
