#pragma once
// Image-based lighting for the local model: the scene's environment (its infinite emitters)
// lighting diffuse surfaces through nine spherical-harmonic coefficients (Ramamoorthi & Hanrahan
// 2001, "An Efficient Representation for Irradiance Environment Maps"), and glossy ones through
// lat-long maps of the environment prefiltered with the Phong lobe of a few roughness levels,
// chosen and interpolated by the surface's roughness. Built once per scene (image_lighting.cpp
// says how); looked up per sample, without allocation.

#include "core/scene.h"

#include <array>
#include <vector>

namespace candela::raster {

class ImageBasedLighting {
public:
    // The scene must have at least one infinite emitter.
    explicit ImageBasedLighting(const Scene& scene);

    // Irradiance (W m^-2) on a surface with unit normal n from the whole, unoccluded
    // environment: E(n) = sum over l <= 2 and m of A_l L_lm Y_lm(n), with A_0 = pi,
    // A_1 = 2 pi / 3, A_2 = pi / 4 (never negative).
    Spectrum irradiance(const Vec3& n) const;
    // The environment seen in direction r by a glossy reflection of microfacet roughness alpha:
    // the environment averaged over the normalised Phong lobe max(w.r, 0)^n around r, with
    // n = phong_exponent(alpha) as the BSDFs map it; alpha 0 is the mirror lookup.
    Spectrum glossy(const Vec3& r, float alpha) const;

    // The nine projection coefficients L_lm in the order of sh_basis.
    const std::array<Spectrum, 9>& coefficients() const { return coefficients_; }
    // The real spherical harmonics Y_00; Y_1-1, Y_10, Y_11; Y_2-2, Y_2-1, Y_20, Y_21, Y_22 at unit
    // direction d = (x, y, z) (Ramamoorthi & Hanrahan, eq. 3).
    static void sh_basis(const Vec3& d, float out[9]);

    // The prefiltered roughness levels (not counting the mirror, alpha 0).
    static constexpr int LevelCount = 5;
    static constexpr float LevelAlphas[LevelCount] = {0.1f, 0.2f, 0.4f, 0.7f, 1.0f};

private:
    // A lat-long map: row j at theta = (j + 0.5) pi / height from +y, column i at
    // phi = (i + 0.5) 2 pi / width around y from +x toward +z.
    struct LatLong {
        int width = 0, height = 0;
        std::vector<Spectrum> texels;
        Spectrum poles[2];  // the values at +y and -y, between which and the first and last
                            // rows lookups interpolate
        Spectrum bilinear(const Vec3& d) const;
    };

    const Scene& scene_;
    std::array<Spectrum, 9> coefficients_;
    std::array<LatLong, LevelCount> levels_;
};

}  // namespace candela::raster
