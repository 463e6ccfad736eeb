// depth: the distance from the camera to the first surface its ray meets, 0 where it meets none
// (Mitsuba 3's `depth` integrator, a debugging view). The distance is along the camera ray from the
// near plane, where Mitsuba's camera rays start, as the aov integrator's depth (core/ray.h).
//
// Parameters: none.
// A sample is valid (the film's alpha) when the ray hits a surface. In scalar_spectral the value is
// that of a grey emission, as ao's, so the film shows the distance as the grey value d in RGB.

#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/spectral.h"
#include "core/wavelengths.h"

namespace candela {

class DepthIntegrator final : public SamplingIntegrator {
public:
    explicit DepthIntegrator(const Properties&) {}

    Spectrum sample_radiance(const Scene& scene, Sampler&, const Ray& ray, SampleRecord& record) const override {
        SurfaceInteraction si;
        if (!scene.intersect(ray, si)) return Spectrum(0.0f);
        record.valid = true;
        record.record_first_hit(si);
        return rgb_at_wavelengths(Spectrum(camera_depth(ray, si.t)), SpectrumRole::Emission, ray.wavelengths);
    }

    std::string to_string() const override { return "depth"; }
};

CANDELA_REGISTER_SPECTRAL(DepthIntegrator, ObjectKind::Integrator, "depth");

}  // namespace candela
