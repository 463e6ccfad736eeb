#include "core/local_model.h"

#include "core/bsdf.h"
#include "core/emitter.h"
#include "core/texture.h"

namespace candela {

LocalShading BSDF::local_shading() const {
    SurfaceInteraction si;
    si.wi = Vec3(0.0f, 0.0f, 1.0f);
    LocalShading s;
    s.diffuse = std::make_shared<ConstantTexture>(albedo(si));
    s.two_sided = (flags_ & Transmission) != 0;
    return s;
}

std::optional<LocalApproximation> Emitter::local_approximation() const { return std::nullopt; }

}  // namespace candela
