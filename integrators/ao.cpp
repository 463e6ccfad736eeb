// ao: ambient occlusion, the classic image of how open each visible point is: the fraction of
// cosine-weighted directions over the hemisphere above it in which nothing lies within
// `ray_length`. A point under an open sky is 1, a point in a closed room (with a long enough ray
// length) is 0, creases and contacts are dark. Materials and lights play no part.
//
// Parameters (Mitsuba 0.6's `ao`, named in Mitsuba 3's style):
//   shading_samples   integer   occlusion rays per camera sample (default 1)
//   ray_length        float     world-space reach of the occlusion rays; negative = automatic:
//                               half the radius of the scene's bounding sphere (default -1)
// The hemisphere is the one on the side the camera sees (around the shading normal, turned
// toward the viewer), so a surface seen from behind is as occluded as its visible side.
// Directions below the geometric surface count as occluded. Camera rays that hit nothing give 1
// (an open background, as in Mitsuba). In scalar_spectral the value is that of a grey emission
// (v times the D65 spectrum of white, core/wavelengths.h), so the film shows the same grey v as
// in RGB, up to the RGB-to-spectrum table's error and the wavelengths' colour noise.

#include "core/bsdf.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/spectral.h"
#include "core/warp.h"
#include "core/wavelengths.h"

namespace candela {

class AmbientOcclusionIntegrator final : public SamplingIntegrator {
public:
    explicit AmbientOcclusionIntegrator(const Properties& props) {
        shading_samples_ = props.get_int("shading_samples", 1);
        if (shading_samples_ <= 0) props.fail("shading_samples", "shading_samples must be positive");
        requested_length_ = props.get_float("ray_length", -1.0f);
        if (requested_length_ == 0.0f) props.fail("ray_length", "ray_length must be positive (or negative for automatic)");
    }

    void prepare(const Scene& scene) override {
        ray_length_ = requested_length_ > 0.0f ? requested_length_ : 0.5f * scene.bbox().bounding_radius();
    }

    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const override {
        SurfaceInteraction si;
        if (!scene.intersect(ray, si)) return grey(1.0f, ray);
        record.valid = true;
        record.record_first_hit(si);
        // The hemisphere on the camera's side of the surface.
        bool back = glm::dot(si.n, ray.d) > 0.0f;
        Vec3 n_geo = back ? -si.n : si.n;
        Frame frame(back ? -si.shading.n : si.shading.n);
        int open = 0;
        for (int i = 0; i < shading_samples_; ++i) {
            Vec3 d = frame.to_world(warp::square_to_cosine_hemisphere(sampler.next_2d()));
            if (glm::dot(d, n_geo) <= 0.0f) continue;  // into the surface itself
            Ray occlusion = si.spawn_ray(d);
            occlusion.tmax = ray_length_;
            if (!scene.occluded(occlusion)) ++open;
        }
        return grey(float(open) / float(shading_samples_), ray);
    }

    std::string to_string() const override { return "ao"; }

private:
    // The value v as the film shows grey v: v itself in RGB, a grey emission at the path's wavelengths.
    static Spectrum grey(float v, const Ray& ray) { return rgb_at_wavelengths(Spectrum(v), SpectrumRole::Emission, ray.wavelengths); }

    int shading_samples_ = 1;
    float requested_length_ = -1.0f, ray_length_ = 1.0f;
};

CANDELA_REGISTER_SPECTRAL(AmbientOcclusionIntegrator, ObjectKind::Integrator, "ao");

}  // namespace candela
