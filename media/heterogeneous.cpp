// heterogeneous: a medium whose coefficients come from volumes (Mitsuba 3's `heterogeneous`).
//
// Parameters:
//   sigma_t           volume, float, rgb or spectrum   extinction coefficient, per scene unit
//                             (default 1); in scalar_spectral an unbounded spectrum
//   albedo            volume, float, rgb or spectrum   single-scattering albedo (default 0.75);
//                             in scalar_spectral a reflectance spectrum
//   scale             float     multiplies sigma_t (default 1)
//   sample_emitters   boolean   next-event estimation from inside the medium (default true)
//   has_spectral_extinction  boolean  accepted for Mitsuba's scenes; both integrators handle a
//                             sigma_t that varies by channel or wavelength in any case
//                             (default true)
//   majorant_resolution_factor  integer  one majorant cell per this many voxels along each axis
//                             of sigma_t (default 8; 0: one global majorant, as Mitsuba 3 uses)
//   (nested phase)            the phase function (default isotropic); a microflake one (sggx)
//                             multiplies sigma_t by its projected area along the ray
// The medium exists only inside sigma_t's bounding box (its unit cube placed by to_world), as in
// Mitsuba; outside, rays cross it as vacuum. Free flights and transmittance walk the majorant
// grid with a DDA, so empty regions of the volume cost a few cell steps and no lookups. In
// scalar_spectral a cell's majorant is one bound for every wavelength: the largest value of a
// grey sigma_t, 2 max(rgb) of a coloured one (the unbounded spectrum of rgb is 2 max(rgb) times
// a sigmoid in [0, 1]), the largest sample of a measured one (core/volume.h), times scale.

#include "core/medium.h"
#include "core/registry.h"
#include "core/volume.h"

namespace candela {

class HeterogeneousMedium : public Medium {
public:
    explicit HeterogeneousMedium(const Properties& props) : Medium(props) {
        sigma_t_ = get_volume(props, "sigma_t", Spectrum(1.0f));
        albedo_ = get_volume(props, "albedo", Spectrum(0.75f));
        scale_ = props.get_float("scale", 1.0f);
        if (!(scale_ >= 0.0f) || !std::isfinite(scale_)) props.fail("scale", "scale must be finite and non-negative");
        props.get_bool("has_spectral_extinction", true);
        int factor = props.get_int("majorant_resolution_factor", 8);
        if (factor < 0) props.fail("majorant_resolution_factor", "majorant_resolution_factor must be 0 (one majorant) or positive");
        if (min_component(sigma_t_->max()) < 0.0f) props.fail("sigma_t", "sigma_t must not be negative");
        Spectrum albedo_max = albedo_->max();
        if (max_component(albedo_max) > 1.0f) props.fail("albedo", "the albedo must lie in [0, 1]");
        glm::ivec3 cells(1);
        if (factor > 0) cells = (sigma_t_->resolution() + glm::ivec3(factor - 1)) / factor;
        majorants_ = MajorantGrid(*sigma_t_, cells, scale_, props.variant() != Variant::ScalarRGB);
    }

    MediumPoint coefficients(const Vec3& p, const Wavelengths* w) const override {
        MediumPoint mp;
        if (w) {
            mp.sigma_t = scale_ * sigma_t_->eval_spectrum(p, *w, SpectrumRole::Unbounded);
            mp.sigma_s = mp.sigma_t * albedo_->eval_spectrum(p, *w, SpectrumRole::Reflectance);
            return mp;
        }
        mp.sigma_t = scale_ * sigma_t_->eval(p);
        mp.sigma_s = mp.sigma_t * albedo_->eval(p);
        return mp;
    }
    std::string to_string() const override { return "heterogeneous"; }

protected:
    MajorantIterator coefficient_majorants(const Ray& ray, float tmax) const override {
        return MajorantIterator(majorants_, ray, ray.tmin, tmax);
    }

private:
    Ref<Volume> sigma_t_, albedo_;
    float scale_ = 1.0f;
    MajorantGrid majorants_;
};

CANDELA_REGISTER_SPECTRAL(HeterogeneousMedium, ObjectKind::Medium, "heterogeneous");

}  // namespace candela
