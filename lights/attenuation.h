#pragma once
// The lecture's distance attenuation of point and spot lights, 1 / (a0 + a1 d + a2 d^2), kept as
// optional parameters whose defaults (0, 0, 1) are the physical inverse-square law. Path tracer
// and rasterizer use the same values, so changing them changes both images alike.

#include "core/properties.h"

namespace candela {

struct Attenuation {
    float constant = 0.0f, linear = 0.0f, quadratic = 1.0f;

    static Attenuation read(const Properties& props) {
        Attenuation a;
        a.constant = props.get_float("attenuation_constant", 0.0f);
        a.linear = props.get_float("attenuation_linear", 0.0f);
        a.quadratic = props.get_float("attenuation_quadratic", 1.0f);
        if (a.constant < 0.0f || a.linear < 0.0f || a.quadratic < 0.0f || a.constant + a.linear + a.quadratic <= 0.0f)
            props.fail("attenuation_constant", "attenuation coefficients must be non-negative and not all zero");
        return a;
    }
    bool physical() const { return constant == 0.0f && linear == 0.0f && quadratic == 1.0f; }
    float operator()(float d) const { return 1.0f / (constant + linear * d + quadratic * d * d); }
};

}  // namespace candela
