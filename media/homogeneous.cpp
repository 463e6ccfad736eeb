// homogeneous: a medium with the same coefficients everywhere (Mitsuba 3's `homogeneous`).
//
// Parameters:
//   sigma_t           float, rgb or constvolume   extinction coefficient, per scene unit
//                                                  (default 1)
//   albedo            float, rgb or volume    single-scattering albedo sigma_s / sigma_t,
//                                              in [0, 1] (default 0.75); a grid gives a spatially
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
// grid's box by its wrap_mode, clamp by default, as Mitsuba's grid lookup does).

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
        Spectrum a = albedo->max();
        if (!all_finite(point_.sigma_t) || min_component(point_.sigma_t) < 0.0f)
            props.fail(props.has("sigma_t") ? "sigma_t" : "scale", "sigma_t * scale must be finite and non-negative");
        if (!all_finite(a) || min_component(a) < 0.0f || max_component(a) > 1.0f) props.fail("albedo", "the albedo must lie in [0, 1]");
        point_.sigma_s = point_.sigma_t * a;
        if (!albedo->is_constant()) albedo_ = albedo;
    }

    MediumPoint coefficients(const Vec3& p) const override {
        if (!albedo_) return point_;
        return MediumPoint{point_.sigma_t, point_.sigma_t * albedo_->eval(p)};
    }
    Spectrum transmittance(const Ray& ray, float tmax, PCG32& rng) const override {
        // A microflake S that varies in space makes sigma_t vary: ratio tracking then.
        if (microflake_ && phase().varies_in_space()) return Medium::transmittance(ray, tmax, rng);
        Spectrum sigma_t = point_.sigma_t * (microflake_ ? phase().max_projected_area(ray.d) : 1.0f);
        float distance = tmax - ray.tmin;
        Spectrum T;
        for (int k = 0; k < 3; ++k) T[k] = sigma_t[k] == 0.0f ? 1.0f : std::exp(-sigma_t[k] * distance);
        return T;
    }
    bool is_homogeneous() const override { return true; }
    std::string to_string() const override { return "homogeneous"; }

protected:
    MajorantIterator coefficient_majorants(const Ray& ray, float tmax) const override {
        return MajorantIterator(ray.tmin, tmax, point_.sigma_t);
    }

private:
    MediumPoint point_;   // sigma_t, and sigma_s for a constant albedo
    Ref<Volume> albedo_;  // a varying albedo (null when constant)
};

CANDELA_REGISTER(HomogeneousMedium, ObjectKind::Medium, "homogeneous");

}  // namespace candela
