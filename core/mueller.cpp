#include "core/mueller.h"

#include "core/bsdf.h"

namespace candela {

Mueller Mueller::identity() {
    Mueller r;
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0f;
    return r;
}

Mueller Mueller::depolarizer(float value) {
    Mueller r;
    r.m[0][0] = value;
    return r;
}

Mueller operator*(const Mueller& a, const Mueller& b) {
    Mueller r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            float sum = 0.0f;
            for (int k = 0; k < 4; ++k) sum += a.m[i][k] * b.m[k][j];
            r.m[i][j] = sum;
        }
    return r;
}

Stokes operator*(const Mueller& a, const Stokes& s) {
    Stokes r(0.0f);
    for (int i = 0; i < 4; ++i) r[i] = a.m[i][0] * s[0] + a.m[i][1] * s[1] + a.m[i][2] * s[2] + a.m[i][3] * s[3];
    return r;
}

Mueller operator*(float f, const Mueller& a) {
    Mueller r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = f * a.m[i][j];
    return r;
}

Mueller operator+(const Mueller& a, const Mueller& b) {
    Mueller r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = a.m[i][j] + b.m[i][j];
    return r;
}

Mueller transpose(const Mueller& a) {
    Mueller r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = a.m[j][i];
    return r;
}

namespace {

Mueller from_rows(std::initializer_list<float> values) {
    Mueller r;
    int k = 0;
    for (float v : values) {
        r.m[k / 4][k % 4] = v;
        ++k;
    }
    return r;
}

}  // namespace

Mueller linear_polarizer(float value) {
    const float a = 0.5f * value;
    return from_rows({a, a, 0, 0, a, a, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
}

Mueller circular_polarizer(bool left_handed) {
    const float h = left_handed ? -0.5f : 0.5f;
    return from_rows({0.5f, 0, 0, h, 0, 0, 0, 0, 0, 0, 0, 0, h, 0, 0, 0.5f});
}

Mueller linear_retarder(float phase) {
    const float s = std::sin(phase), c = std::cos(phase);
    return from_rows({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, c, s, 0, 0, -s, c});
}

Mueller diattenuator(float x, float y) {
    const float a = 0.5f * (x + y), b = 0.5f * (x - y), c = std::sqrt(x * y);
    return from_rows({a, b, 0, 0, b, a, 0, 0, 0, 0, c, 0, 0, 0, 0, c});
}

Mueller rotator(float theta) {
    const float s = std::sin(2.0f * theta), c = std::cos(2.0f * theta);
    return from_rows({1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, 0, 0, 0, 1});
}

Mueller rotated_element(float theta, const Mueller& M) {
    const Mueller R = rotator(theta);
    return transpose(R) * M * R;
}

FresnelAmplitudes fresnel_amplitudes(float cos_theta_i, std::complex<float> eta) {
    using C = std::complex<float>;
    FresnelAmplitudes f;
    const bool outside = cos_theta_i >= 0.0f;
    const C eta_it = outside ? eta : 1.0f / eta, eta_ti = outside ? 1.0f / eta : eta;
    const C cos_t_sqr = 1.0f - eta_ti * eta_ti * (1.0f - cos_theta_i * cos_theta_i);
    const float cos_i = std::abs(cos_theta_i);
    // The root's sign follows Re(cos_t^2): it sets the phase under total internal reflection
    // (Clarke, "Stellar Polarimetry", app. A.2).
    C cos_t = std::sqrt(cos_t_sqr);
    if (cos_t_sqr.real() < 0.0f) cos_t = -cos_t;
    // Verdet's sign of a_p, as Mitsuba 3: a_s and a_p have opposite signs at normal incidence.
    f.a_s = (cos_i - eta_it * cos_t) / (cos_i + eta_it * cos_t);
    f.a_p = (eta_it * cos_i - cos_t) / (eta_it * cos_i + cos_t);
    const bool matched = std::norm(eta) == 1.0f && eta.imag() == 0.0f;
    if (matched || std::norm(eta) == 0.0f) f.a_s = f.a_p = C(0.0f);
    f.cos_theta_t = cos_t_sqr.real() >= 0.0f ? (outside ? -cos_t.real() : cos_t.real()) : 0.0f;
    f.eta_it = eta_it.real();
    f.eta_ti = eta_ti.real();
    return f;
}

Mueller specular_reflection(float cos_theta_i, std::complex<float> eta) {
    const FresnelAmplitudes f = fresnel_amplitudes(cos_theta_i, eta);
    const float r_s = std::norm(f.a_s), r_p = std::norm(f.a_p);
    const float a = 0.5f * (r_s + r_p), b = 0.5f * (r_s - r_p), c = std::sqrt(r_s * r_p);
    // The phase delay arg(a_p) - arg(a_s), from a_p conj(a_s).
    const std::complex<float> z = f.a_p * std::conj(f.a_s);
    const float len = std::abs(z);
    const float cos_delta = len > 0.0f ? z.real() / len : 0.0f, sin_delta = len > 0.0f ? z.imag() / len : 0.0f;
    return from_rows({a, b, 0, 0, b, a, 0, 0, 0, 0, c * cos_delta, -c * sin_delta, 0, 0, c * sin_delta, c * cos_delta});
}

Mueller specular_transmission(float cos_theta_i, float eta) {
    const FresnelAmplitudes f = fresnel_amplitudes(cos_theta_i, std::complex<float>(eta, 0.0f));
    // Transmitted power per unit area of the beam: eta_it cos_t / cos_i (cos_t has the opposite sign).
    const float factor = std::abs(cos_theta_i) > 1e-8f ? -f.eta_it * f.cos_theta_t / cos_theta_i : 0.0f;
    // Amplitude transmission coefficients t_s = 1 + r_s, t_p = (1 + r_p) n_i / n_t (Verdet signs).
    const float t_s = sqr(1.0f + f.a_s.real()), t_p = sqr((1.0f + f.a_p.real()) * f.eta_ti);
    const float a = 0.5f * factor * (t_s + t_p), b = 0.5f * factor * (t_s - t_p), c = factor * std::sqrt(t_s * t_p);
    return from_rows({a, b, 0, 0, b, a, 0, 0, 0, 0, c, 0, 0, 0, 0, c});
}

Mueller rotate_stokes_basis(const Vec3& forward, const Vec3& current, const Vec3& target) {
    // The signed angle theta from current to target about forward, through its cosine and sine
    // (not an arccosine, which loses half the digits near 0 and pi, where most turns between
    // nearby bases are): cos 2 theta and sin 2 theta by the double-angle formulas.
    const float c = glm::dot(current, target), s = glm::dot(forward, glm::cross(current, target));
    const float r2 = c * c + s * s;
    if (!(r2 > 0.0f)) return Mueller::identity();
    const float cos2 = (c * c - s * s) / r2, sin2 = 2.0f * c * s / r2;
    return from_rows({1, 0, 0, 0, 0, cos2, sin2, 0, 0, -sin2, cos2, 0, 0, 0, 0, 1});
}

Mueller rotate_mueller_basis(const Mueller& M, const Vec3& in_forward, const Vec3& in_current, const Vec3& in_target,
                             const Vec3& out_forward, const Vec3& out_current, const Vec3& out_target) {
    const Mueller R_in = rotate_stokes_basis(in_forward, in_current, in_target);
    const Mueller R_out = rotate_stokes_basis(out_forward, out_current, out_target);
    return R_out * M * transpose(R_in);
}

BasisChange local_to_parent(const Frame& frame, const Vec3& wi, const Vec3& wo) {
    const Vec3 in_local = -wo, in_parent = frame.to_world(in_local);
    const Vec3 out_parent = frame.to_world(wi);
    return BasisChange{rotate_stokes_basis(out_parent, frame.to_world(stokes_basis(wi)), stokes_basis(out_parent)),
                       transpose(rotate_stokes_basis(in_parent, frame.to_world(stokes_basis(in_local)), stokes_basis(in_parent)))};
}

BasisChange facet_to_local_bases(const Vec3& m, const Vec3& wi, const Vec3& wo) {
    // The s axis is perpendicular to the plane of incidence; when the light travels along the
    // normal every axis is, and both take the first tangent of m's frame (the x axis for +z).
    Vec3 s_in = glm::cross(m, -wo), s_out = glm::cross(m, wi);
    const float len_in = glm::length(s_in), len_out = glm::length(s_out);
    s_in = len_in > 1e-7f ? s_in / len_in : stokes_basis(m);
    s_out = len_out > 1e-7f ? s_out / len_out : stokes_basis(m);
    return BasisChange{rotate_stokes_basis(wi, s_out, stokes_basis(wi)), transpose(rotate_stokes_basis(-wo, s_in, stokes_basis(-wo)))};
}

MuellerSpectrum identity_spectrum() {
    MuellerSpectrum r;
    for (Mueller& m : r.w) m = Mueller::identity();
    return r;
}

bool normalized_world_mueller(const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                              MuellerSpectrum& N) {
    if (!bsdf.eval_mueller(ctx, si, wo, lobe, N)) return false;
    const BasisChange to_world = local_to_parent(si.shading, si.wi, wo);
    for (Mueller& m : N.w) {
        const float m00 = m.m[0][0];
        m = m00 > 0.0f && std::isfinite(m00) ? (1.0f / m00) * to_world.apply(m) : Mueller();
    }
    return true;
}

namespace {

// Per wavelength, a = a b.
void multiply_right(MuellerSpectrum& a, const MuellerSpectrum& b) {
    for (int k = 0; k < 3; ++k) a.w[k] = a.w[k] * b.w[k];
}

// Per wavelength, a = a diag(1, 0, 0, 0): only light of the intensity S0 goes on.
void multiply_right_depolarizer(MuellerSpectrum& a) {
    for (Mueller& m : a.w)
        for (int i = 0; i < 4; ++i) m.m[i][1] = m.m[i][2] = m.m[i][3] = 0.0f;
}

}  // namespace

void multiply_by_bsdf(MuellerSpectrum& product, const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo,
                      uint32_t lobe) {
    MuellerSpectrum N;
    if (normalized_world_mueller(bsdf, ctx, si, wo, lobe, N))
        multiply_right(product, N);
    else
        multiply_right_depolarizer(product);
}

void scatter_stokes(const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                    StokesSpectrum& s) {
    MuellerSpectrum N;
    if (!normalized_world_mueller(bsdf, ctx, si, wo, lobe, N)) {
        for (Stokes& v : s.w) v = Stokes(v[0], 0.0f, 0.0f, 0.0f);
        return;
    }
    for (int k = 0; k < 3; ++k) s.w[k] = N.w[k] * s.w[k];
}

float degree_of_polarization(const Stokes& s) { return s[0] > 0.0f ? std::sqrt(s[1] * s[1] + s[2] * s[2] + s[3] * s[3]) / s[0] : 0.0f; }

}  // namespace candela
