#pragma once
// Polarisation for the scalar_spectral_polarized variant: Stokes vectors, Mueller matrices and
// the reference frames they are expressed in, with Mitsuba 3's conventions (its
// render/mueller.h documents them; the formulas are Collett's "Polarized Light" and Goldstein's
// third edition).
//
// A Stokes vector (S0 intensity, S1 horizontal minus vertical, S2 +45 minus -45 degrees, S3 right
// minus left circular) means something only with its reference basis: a unit vector orthogonal
// to the direction the light travels, observed from the sensor looking back along the beam.
// Candela, as Mitsuba, never stores bases: the basis of light travelling along w is
// stokes_basis(w), the first tangent of coordinate_system(w) (core/frame.h). A Mueller matrix maps
// a Stokes vector in one basis to one in another, and rotate_mueller_basis re-expresses it.
//
// Matrices are row-major (m[row][col]), one per wavelength of the path (MuellerSpectrum).

#include "core/frame.h"
#include "core/spectrum.h"

#include <complex>

namespace candela {

using Stokes = glm::vec4;

struct Mueller {
    float m[4][4] = {};

    static Mueller identity();
    // Only the (0, 0) element: an ideal depolariser (what every unpolarised BSDF is).
    static Mueller depolarizer(float value = 1.0f);
    float operator()(int row, int col) const { return m[row][col]; }
    float& operator()(int row, int col) { return m[row][col]; }
};

Mueller operator*(const Mueller& a, const Mueller& b);
Stokes operator*(const Mueller& a, const Stokes& s);
Mueller operator*(float f, const Mueller& a);
Mueller operator+(const Mueller& a, const Mueller& b);
Mueller transpose(const Mueller& a);

// One Mueller matrix per wavelength of the path (WavelengthSamples of them, as a Spectrum holds).
struct MuellerSpectrum {
    Mueller w[3];
};
// One Stokes vector per wavelength.
struct StokesSpectrum {
    Stokes w[3]{Stokes(0.0f), Stokes(0.0f), Stokes(0.0f)};
    // The components S_k at the three wavelengths, as a Spectrum.
    Spectrum component(int k) const { return Spectrum(w[0][k], w[1][k], w[2][k]); }
};

// Ideal elements (Collett ch. 5; Goldstein eq. 6.43 for the retarder, fast axis horizontal).
Mueller linear_polarizer(float value = 1.0f);
Mueller linear_retarder(float phase);
// Passes right-handed circularly polarised light (S3 > 0, Mitsuba's convention), or left-handed:
// 1/2 [[1, 0, 0, h], [0, 0, 0, 0], [0, 0, 0, 0], [h, 0, 0, 1]], h = +1 or -1.
Mueller circular_polarizer(bool left_handed);
// Attenuates the field's components at 0 and 90 degrees to intensities x and y.
Mueller diattenuator(float x, float y);
// Rotates the reference frame by theta (radians, counter-clockwise seen from the sensor):
// horizontal light [1, 1, 0, 0] becomes [1, 0, -1, 0] under rotator(45 degrees).
Mueller rotator(float theta);
// An element turned by theta about the beam: rotator(-theta) M rotator(theta).
Mueller rotated_element(float theta, const Mueller& M);

// Fresnel amplitudes of the s- and p-polarised reflected waves for the complex relative index
// eta (eta > 1 when the normal points to the thinner side; cos_theta_i < 0 means incidence from
// inside), with Fresnel's 1823 sign of a_p (Mitsuba's fresnel_polarized; Clarke, "Stellar
// Polarimetry", app. A). Also the signed cosine of the transmitted ray (0 under total internal
// reflection) and the real part of eta_it (the index ratio along the light's travel).
struct FresnelAmplitudes {
    std::complex<float> a_s, a_p;
    float cos_theta_t = 0.0f;
    float eta_it = 1.0f, eta_ti = 1.0f;
};
FresnelAmplitudes fresnel_amplitudes(float cos_theta_i, std::complex<float> eta);

// The Mueller matrices of specular reflection and transmission at an interface, in the frame
// whose basis is perpendicular to the plane of incidence (s). Their (0, 0) elements are the
// unpolarised Fresnel reflectance and 1 minus it.
Mueller specular_reflection(float cos_theta_i, std::complex<float> eta);
Mueller specular_transmission(float cos_theta_i, float eta);

// The implicit basis of light travelling along unit vector `forward`.
inline Vec3 stokes_basis(const Vec3& forward) {
    Vec3 s, t;
    coordinate_system(forward, s, t);
    return s;
}
// The rotation that re-expresses a Stokes vector travelling along `forward` from basis
// `current` to basis `target` (both unit vectors orthogonal to forward).
Mueller rotate_stokes_basis(const Vec3& forward, const Vec3& current, const Vec3& target);
// M, mapping in_current to out_current, re-expressed from in_target to out_target.
Mueller rotate_mueller_basis(const Mueller& M, const Vec3& in_forward, const Vec3& in_current, const Vec3& in_target,
                             const Vec3& out_forward, const Vec3& out_current, const Vec3& out_target);

// A change of the input and output bases of Mueller matrices: M -> out M in_transposed, the same
// rotations for every wavelength (computed once).
struct BasisChange {
    Mueller out, in_transposed;
    Mueller apply(const Mueller& M) const { return out * M * in_transposed; }
    void apply(MuellerSpectrum& M) const {
        for (Mueller& m : M.w) m = apply(m);
    }
};
// For a BSDF's matrices of light that arrives along -wo and leaves along wi (directions in the
// local frame `frame`), expressed in the implicit bases of -wo and wi in that frame: the change to
// the implicit bases of the same directions in the frame's parent coordinates (world space for a
// shading frame; the shading frame for a perturbed one).
BasisChange local_to_parent(const Frame& frame, const Vec3& wi, const Vec3& wo);
// For matrices of reflection (or transmission) at a facet with normal m (the frame's normal for a
// smooth surface), given in the s/p frame of the plane of incidence: the change to the implicit
// local bases of -wo and wi, as BSDF::eval_mueller returns them.
BasisChange facet_to_local_bases(const Vec3& m, const Vec3& wi, const Vec3& wo);

class BSDF;
struct BSDFContext;
struct SurfaceInteraction;

MuellerSpectrum identity_spectrum();

// What the polarized variant's paths use of a BSDF: BSDF::eval_mueller in world bases, divided
// by its (0, 0) element per wavelength (zero where that is not positive). False when the BSDF
// depolarises (N untouched).
bool normalized_world_mueller(const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                              MuellerSpectrum& N);

// A path's product of normalised matrices grown by one element further from the camera:
// product = product N, N normalized_world_mueller's matrix, or the depolariser where the BSDF
// depolarises.
void multiply_by_bsdf(MuellerSpectrum& product, const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo,
                      uint32_t lobe);
// The normalised Stokes vectors `s` of light that arrives along -wo (local) after `lobe` of `bsdf`
// sends it along si.wi: normalized_world_mueller's matrix applied, or only S0 kept where the BSDF
// depolarises.
void scatter_stokes(const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                    StokesSpectrum& s);
// The first column of M: what M makes of unpolarised light of unit intensity.
inline Stokes first_column(const Mueller& M) { return Stokes(M.m[0][0], M.m[1][0], M.m[2][0], M.m[3][0]); }

// Degree of polarisation sqrt(S1^2 + S2^2 + S3^2) / S0 (0 for S0 = 0).
float degree_of_polarization(const Stokes& s);

}  // namespace candela
