#pragma once
// The local-illumination view of the scene, for the rasterizer only: how a BSDF maps to the
// lecture's Phong / Blinn-Phong model with environment mapping, and how a non-delta emitter is
// approximated (area lights as points, environments as ambient). The path tracer never reads
// these; they sit here, apart from the physical interfaces in bsdf.h and emitter.h.

#include "core/object.h"
#include "core/spectrum.h"

namespace candela {

class Shape;
class Texture;

// How the local model approximates a BSDF. Each BSDF documents its own mapping in
// local_shading(); the default (BSDF::local_shading) is a Lambertian of the BSDF's albedo.
struct LocalShading {
    Ref<Texture> diffuse;         // Lambertian albedo kd (the model uses kd / pi); null: none
    Spectrum specular{0.0f};      // weight ks of the glossy highlight (normalised by the model)
    float shininess = 0.0f;       // exponent n of the highlight; 0: no highlight
    Spectrum mirror{0.0f};        // weight of the environment seen in the mirror direction
    Spectrum transmission{0.0f};  // weight of the environment seen through by refraction
    float eta = 1.0f;             // relative IOR for that refraction (1: straight through)
    float roughness = 0.0f;       // microfacet alpha: blurs the environment reflections
    bool two_sided = false;       // lit from both sides
    Ref<Texture> height;          // bump height field (bumpmap): displacement mapping uses it
    float height_scale = 1.0f;
};

// How the local model approximates an emitter that is not a delta light (delta lights it
// evaluates exactly, through sample_direction).
struct LocalApproximation {
    enum class Kind { Ambient, AreaPoint };
    Kind kind = Kind::Ambient;
    // Ambient: the uniform ambient radiance of an environment. AreaPoint: the radiance the
    // emitting surface shows on its front side.
    Spectrum radiance{0.0f};
    // AreaPoint: a point light at `position` with radiant intensity `intensity` along `normal`
    // times max(0, cos) when `planar`, and the same in every direction otherwise. `shape` is the
    // emitting shape, which must not shadow its own light.
    const Shape* shape = nullptr;
    Vec3 position{0.0f}, normal{0.0f, 0.0f, 1.0f};
    bool planar = false;
    Spectrum intensity{0.0f};
};

}  // namespace candela
