// The fog pass: the medium the camera stands in, as OpenGL's exponential fog (GL_EXP). Each
// camera sample's colour c at distance d from the eye becomes
//   c * exp(-sigma_t d) + fog * (1 - exp(-sigma_t d)),   fog = albedo * ambient,
// per channel: the attenuation of what the surface sends is Beer-Lambert's, exact for a
// homogeneous medium; the light scattered in along the way is approximated by the medium's
// albedo times the frame's ambient light (the environment's average and the `ambient` setting),
// the local model's stand-in for light arriving from everywhere. Where no surface is, d is
// infinite and the fog colour alone remains. A heterogeneous medium around the camera is taken
// with its coefficients at the eye. Media inside shapes are not drawn (RasterIntegrator warns).

#include "core/medium.h"
#include "core/parallel.h"
#include "core/scene.h"
#include "integrators/raster/frame.h"

namespace candela::raster {

void fog_pass(const FrameSetup& f, FrameBuffers& b) {
    const Medium* medium = f.scene.sensor().medium();
    if (!medium) return;
    // The coefficients without a microflake phase function's projected area, which depends on
    // the view direction: one fog colour and density for the whole frame is the approximation.
    const MediumPoint mp = medium->coefficients(f.camera.eye);
    Spectrum albedo(0.0f);
    for (int k = 0; k < 3; ++k) albedo[k] = mp.sigma_t[k] > 0.0f ? mp.sigma_s[k] / mp.sigma_t[k] : 0.0f;
    const Spectrum fog = albedo * f.ambient;
    parallel_for(f.sample_count(), [&](size_t i) {
        float d = b.triangle[i] == NoTriangle ? Infinity : glm::length(b.surface[i].p - f.camera.eye);
        Spectrum T;
        for (int k = 0; k < 3; ++k) T[k] = mp.sigma_t[k] == 0.0f ? 1.0f : std::exp(-mp.sigma_t[k] * d);
        b.color[i] = b.color[i] * T + fog * (Spectrum(1.0f) - T);
    });
}

}  // namespace candela::raster
