// sggx: the SGGX microflake phase function (Heitz, Dupuy, Crassin and Dachsbacher 2015, "The
// SGGX Microflake Distribution"; Mitsuba 3's `sggx`): a medium of small specular flakes whose
// normals are distributed as the normals of an ellipsoid, given by a symmetric positive definite
// matrix S. It models fibres (S flat along the fibre) and surface-like volumes (S long along
// the normal).
//
// Parameters:
//   S   volume   the six entries S_xx, S_yy, S_zz, S_xy, S_xz, S_yz at each point (no unit; only
//                S's shape and scale relative to the identity matter): a gridvolume of six
//                channels (Mitsuba 3's form) or a constvolume whose `value` is a string of six
//                numbers. Required. As in Mitsuba, a grid's S must be positive definite in every
//                voxel (not checked); a constant S is checked.
//
// Formulas (the paper's section 3 and 4; wi points back along the path, as in Mitsuba):
//   D(m)      = 1 / (pi sqrt(det S) (m^T S^-1 m)^2)
//             = det(S)^(3/2) / (pi (m^T adj(S) m)^2)        (the microflake normal density)
//   sigma(w)  = sqrt(w^T S w)                              (projected area along w)
//   p(wi, wo) = D(h) / (4 sigma(wi)),  h = (wi + wo) / |wi + wo|   (specular flakes)
// Sampling draws a visible normal from D_wi(m) = <wi, m> D(m) / sigma(wi) (the paper's
// Algorithm, a cosine-weighted disk mapped through S's Cholesky-like factor in a frame around
// wi) and reflects wi about it: its pdf is exactly p, so the weight is 1.
// A medium with this phase function has extinction sigma_t(p) sigma(wi) (Mitsuba 3 multiplies by
// projected_area in its media). p is not symmetric in (wi, wo); sigma(wi) p(wi, wo) is.
// With S = identity: D = 1 / pi, sigma = 1, p = 1 / (4 pi), the isotropic phase function.

#include "core/phase.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/volume.h"
#include "core/warp.h"

namespace candela {

namespace {

// S as its six entries, Mitsuba's order.
struct SggxMatrix {
    float xx, yy, zz, xy, xz, yz;

    float quadratic_form(const Vec3& w) const {
        return w.x * w.x * xx + w.y * w.y * yy + w.z * w.z * zz + 2.0f * (w.x * w.y * xy + w.x * w.z * xz + w.y * w.z * yz);
    }
    float determinant() const { return xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz); }
    // m^T adj(S) m, which is det(S) m^T S^-1 m without the inverse.
    float adjugate_form(const Vec3& m) const {
        return m.x * m.x * (yy * zz - yz * yz) + m.y * m.y * (xx * zz - xz * xz) + m.z * m.z * (xx * yy - xy * xy) +
               2.0f * (m.x * m.y * (xz * yz - zz * xy) + m.x * m.z * (xy * yz - yy * xz) + m.y * m.z * (xy * xz - xx * yz));
    }
    // Positive definite: Sylvester's criterion on the leading minors.
    bool positive_definite() const { return xx > 0.0f && xx * yy - xy * xy > 0.0f && determinant() > 0.0f; }
};

// The microflake normal density D(m) for a unit m (0 where S is not positive definite).
float sggx_ndf(const SggxMatrix& S, const Vec3& m) {
    float det = S.determinant(), form = S.adjugate_form(m);
    if (!(det > 0.0f) || !(form > 0.0f)) return 0.0f;
    return det * std::sqrt(det) / (Pi * form * form);
}

float sggx_sigma(const SggxMatrix& S, const Vec3& w) { return safe_sqrt(S.quadratic_form(w)); }

// A visible normal for direction wi (Heitz et al. 2015, appendix: sampling D_wi). S is written
// in an orthonormal frame (k, j, i) with i = wi; a cosine-distributed point of the unit disk
// lifted to the hemisphere is mapped by the columns M_k, M_j, M_i, which take the hemisphere
// around i to the visible half of the ellipsoid.
Vec3 sample_visible_normal(const SggxMatrix& S, const Vec3& wi, const Vec2& u) {
    Frame frame(wi);
    const Vec3 axes[3] = {frame.s, frame.t, frame.n};  // k, j, i
    Mat3 s_world(Vec3(S.xx, S.xy, S.xz), Vec3(S.xy, S.yy, S.yz), Vec3(S.xz, S.yz, S.zz));
    float s_local[3][3];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) s_local[a][b] = glm::dot(axes[a], s_world * axes[b]);
    const int k = 0, j = 1, i = 2;
    float det = S.determinant();
    float inv_sqrt_ii = 1.0f / safe_sqrt(s_local[i][i]);
    float tmp = safe_sqrt(s_local[j][j] * s_local[i][i] - s_local[j][i] * s_local[j][i]);
    Vec3 m_k(safe_sqrt(det) / tmp, 0.0f, 0.0f);
    Vec3 m_j(-inv_sqrt_ii * (s_local[k][i] * s_local[j][i] - s_local[k][j] * s_local[i][i]) / tmp, inv_sqrt_ii * tmp, 0.0f);
    Vec3 m_i = inv_sqrt_ii * Vec3(s_local[k][i], s_local[j][i], s_local[i][i]);
    Vec3 uvw = warp::square_to_cosine_hemisphere(u);
    return frame.to_world(glm::normalize(uvw.x * m_k + uvw.y * m_j + uvw.z * m_i));
}

}  // namespace

class SggxPhase : public PhaseFunction {
public:
    explicit SggxPhase(const Properties& props) {
        if (!props.has("S")) props.fail("sggx needs its matrix S (a volume of six values)");
        Properties::Type type;
        const Properties::Value& raw = props.get_raw("S", &type);
        Ref<Object> object = type == Properties::Type::Object ? std::get<Ref<Object>>(raw) : nullptr;
        if (!object || object->kind() != ObjectKind::Volume) props.fail("S", "sggx: S must be a volume of six values");
        S_ = std::static_pointer_cast<Volume>(object);
        if (S_->channel_count() != 6)
            props.fail("S",
                       "sggx: S must have six values (S_xx, S_yy, S_zz, S_xy, S_xz, S_yz), not " + std::to_string(S_->channel_count()));
        float max[6];
        S_->max_channels(max);
        if (S_->is_constant()) {
            constant_ = matrix_from(max);
            if (!constant_.positive_definite()) props.fail("S", "sggx: S must be positive definite");
        }
        // For a varying S: the largest eigenvalue of a positive definite S is at most its trace,
        // so sigma(w)^2 <= max S_xx + max S_yy + max S_zz everywhere.
        trace_bound_ = std::max(max[0], 0.0f) + std::max(max[1], 0.0f) + std::max(max[2], 0.0f);
    }

    float eval(const MediumInteraction& mi, const Vec3& wo) const override {
        SggxMatrix S = matrix_at(mi.p);
        Vec3 h = mi.wi + wo;
        float length = glm::length(h);
        float sigma = sggx_sigma(S, mi.wi);
        if (!(length > 0.0f) || !(sigma > 0.0f)) return 0.0f;
        return sggx_ndf(S, h / length) / (4.0f * sigma);
    }
    float pdf(const MediumInteraction& mi, const Vec3& wo) const override { return eval(mi, wo); }

    PhaseSample sample(const MediumInteraction& mi, const Vec2& u) const override {
        SggxMatrix S = matrix_at(mi.p);
        PhaseSample ps;
        Vec3 m = sample_visible_normal(S, mi.wi, u);
        if (!all_finite(m)) return ps;
        ps.wo = glm::normalize(2.0f * glm::dot(mi.wi, m) * m - mi.wi);  // wi reflected about m
        ps.pdf = pdf(mi, ps.wo);
        ps.weight = ps.pdf > 0.0f ? 1.0f : 0.0f;
        return ps;
    }

    bool is_microflake() const override { return true; }
    float projected_area(const MediumInteraction& mi) const override { return sggx_sigma(matrix_at(mi.p), mi.wi); }
    float max_projected_area(const Vec3& d) const override {
        if (S_->is_constant()) return sggx_sigma(constant_, d / glm::length(d));
        return std::sqrt(trace_bound_);
    }
    bool varies_in_space() const override { return !S_->is_constant(); }
    std::string to_string() const override { return "sggx"; }

private:
    static SggxMatrix matrix_from(const float* v) { return SggxMatrix{v[0], v[1], v[2], v[3], v[4], v[5]}; }
    SggxMatrix matrix_at(const Vec3& p) const {
        if (S_->is_constant()) return constant_;
        float v[6];
        S_->eval_channels(p, v);
        return matrix_from(v);
    }

    Ref<Volume> S_;
    SggxMatrix constant_{1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f};
    float trace_bound_ = 3.0f;
};

CANDELA_REGISTER_SPECTRAL(SggxPhase, ObjectKind::Phase, "sggx");

}  // namespace candela
