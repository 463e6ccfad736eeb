// homogeneous: a medium with the same coefficients everywhere (Mitsuba 3's `homogeneous`).
//
// Parameters:
//   sigma_t           float, rgb, spectrum or constvolume   extinction coefficient, per scene
//                                              unit (default 1); in scalar_spectral an unbounded
//                                              spectrum (rgb: 2 max(rgb) times a sigmoid; a
//                                              measured spectrum per wavelength)
//   albedo            float, rgb, spectrum or volume   single-scattering albedo sigma_s / sigma_t,
//                                              in [0, 1] (default 0.75; in scalar_spectral a
//                                              reflectance spectrum); a grid gives a spatially
//                                              varying albedo, as Mitsuba 3 allows (its docs scene
//                                              medium_homogeneous_sss_textured)
//   scale             float     multiplies sigma_t, e.g. to change units (default 1)
//   sample_emitters   boolean   next-event estimation from inside the medium (default true)
//   (nested phase)              the phase function (default isotropic); a microflake one (sggx)
//                               multiplies sigma_t by its projected area along the ray, so
//                               sigma_t depends on the direction (and on the point, where S does)
// It fills whatever region refers to it (a shape's interior or exterior, a sensor's
// surroundings), without bounds of its own. Transmittance is exact: exp(-sigma_t * distance)
// (ratio tracking only for an sggx phase function whose S varies),
// since only the albedo may vary; a grid albedo is looked up where the path collides (beyond the
// grid's box by its wrap_mode, clamp by default, as Mitsuba's grid lookup does). In scalar_spectral
// sigma_t at the path's wavelengths is its own majorant and its transmittance is exact per
// wavelength.

#include "core/medium.h"
#include "core/registry.h"
#include "core/volume.h"

namespace candela {

class HomogeneousMedium : public Medium {
public:
    explicit HomogeneousMedium(const Properties& props) : Medium(props) {
        Ref<Volume> sigma_t = get_volume(props, "sigma_t", Spectrum(1.0f)), albedo = get_volume(props, "albedo", Spectrum(0.75f));
        if (!sigma_t->is_constant())
            props.fail("sigma_t", "a homogeneous medium needs a constant sigma_t (use a heterogeneous medium for a grid)");
        float scale = props.get_float("scale", 1.0f);
        point_.sigma_t = sigma_t->max() * scale;
        scale_ = scale;
        if (props.variant() != Variant::ScalarRGB) {
            sigma_t_ = sigma_t;
            spectral_albedo_ = albedo;
        }
        Spectrum a = albedo->max();
        if (!all_finite(point_.sigma_t) || min_component(point_.sigma_t) < 0.0f)
            props.fail(props.has("sigma_t") ? "sigma_t" : "scale", "sigma_t * scale must be finite and non-negative");
        if (!all_finite(a) || min_component(a) < 0.0f || max_component(a) > 1.0f) props.fail("albedo", "the albedo must lie in [0, 1]");
        point_.sigma_s = point_.sigma_t * a;
        if (!albedo->is_constant()) albedo_ = albedo;
    }

    MediumPoint coefficients(const Vec3& p, const Wavelengths* w) const override {
        if (w) {
            const Spectrum sigma_t = sigma_t_at(*w);
            return MediumPoint{sigma_t, sigma_t * spectral_albedo_->eval_spectrum(p, *w, SpectrumRole::Reflectance)};
        }
        if (!albedo_) return point_;
        return MediumPoint{point_.sigma_t, point_.sigma_t * albedo_->eval(p)};
    }
    Spectrum transmittance(const Ray& ray, float tmax, PCG32& rng) const override {
        // A microflake S that varies in space makes sigma_t vary: ratio tracking then.
        if (microflake_ && phase().varies_in_space()) return Medium::transmittance(ray, tmax, rng);
        Spectrum sigma_t =
            (ray.wavelengths ? sigma_t_at(*ray.wavelengths) : point_.sigma_t) * (microflake_ ? phase().max_projected_area(ray.d) : 1.0f);
        float distance = tmax - ray.tmin;
        Spectrum T;
        for (int k = 0; k < 3; ++k) T[k] = sigma_t[k] == 0.0f ? 1.0f : std::exp(-sigma_t[k] * distance);
        return T;
    }
    bool is_homogeneous() const override { return true; }
    std::string to_string() const override { return "homogeneous"; }

protected:
    MajorantIterator coefficient_majorants(const Ray& ray, float tmax) const override {
        // sigma_t is the same everywhere: at each wavelength it is its own (tightest) majorant.
        return MajorantIterator(ray.tmin, tmax, ray.wavelengths ? sigma_t_at(*ray.wavelengths) : point_.sigma_t);
    }

private:
    // sigma_t * scale at the wavelengths, as an unbounded spectrum (or a measured one).
    Spectrum sigma_t_at(const Wavelengths& w) const { return sigma_t_->eval_spectrum(Vec3(0.0f), w, SpectrumRole::Unbounded) * scale_; }

    MediumPoint point_;   // sigma_t, and sigma_s for a constant albedo
    Ref<Volume> albedo_;  // a varying albedo (null when constant)
    // The spectral variant's: sigma_t (constant) and the albedo, looked up at the wavelengths.
    Ref<Volume> sigma_t_, spectral_albedo_;
    float scale_ = 1.0f;
};

CANDELA_REGISTER_SPECTRAL(HomogeneousMedium, ObjectKind::Medium, "homogeneous");

}  // namespace candela
