#pragma once
// The local model's view of composite BSDFs (blendbsdf, mask, and the principled BSDFs' scaled
// base colour): textures combined texel by texel, and LocalShading blended field by field.

#include "core/local_model.h"
#include "core/texture.h"

namespace candela {

// (1 - w) a + w b at every uv, w a scalar texture (eval_1, clamped to [0, 1]); a null side is
// black; null when both are.
Ref<Texture> mix_textures(const Ref<Texture>& a, const Ref<Texture>& b, const Ref<Texture>& weight);
// factor * t (null stays null; a factor of 1 returns t itself).
Ref<Texture> scaled_texture(const Ref<Texture>& t, float factor);
// The blend (1 - w) a + w b of two local models: Lambertian textures texel by texel, the other
// weights by the mean of w; the highlight exponent, refraction index and height field of the side
// that contributes more.
LocalShading mix_local_shading(const LocalShading& a, const LocalShading& b, const Ref<Texture>& weight);

}  // namespace candela
