// irradiance: renders, for each pixel, the irradiance (W m^-2) at the first surface the camera
// sees, on the side facing the camera: the lighting designer's map. All light arriving there is
// counted, direct and indirect. Pixels that see no surface are 0.
//
// Parameters:
//   max_depth, rr_depth, light_sampler   as `path` (they bound the paths that bring light)
//   max_value                            top of the false-colour scale of the PNG preview
//                                        (default: the 99th percentile of the image)

#include "core/bsdf.h"
#include "core/image_draw.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "integrators/estimators.h"
#include "integrators/path.h"

#include <cstdio>

namespace candela {

class IrradianceIntegrator final : public SamplingIntegrator {
public:
    explicit IrradianceIntegrator(const Properties& props) : path_(read_path_settings(props, DepthSettings | LightSamplerSetting)) {
        max_value_ = props.get_float("max_value", 0.0f);
        if (max_value_ < 0.0f) props.fail("max_value", "max_value must be positive");
    }

    void prepare(const Scene& scene) override { path_.prepare(scene); }

    // A sample is valid (the film's alpha) when it finds a surface.
    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const override {
        SurfaceInteraction si;
        if (!scene.intersect(ray, si)) return Spectrum(0.0f);
        record.valid = true;
        record.record_first_hit(si);
        // A white Lambertian receiver on the camera's side of the surface.
        Vec3 n = glm::dot(si.n, ray.d) < 0.0f ? si.n : -si.n;
        SurfaceInteraction vertex = si;
        vertex.n = n;
        vertex.shading = Frame(n);
        vertex.wi = Vec3(0.0f, 0.0f, 1.0f);
        return Pi * path_.continue_path(scene, sampler, vertex, white_lambertian(), 0);
    }

    // False colour on a linear scale with a legend in W/m^2.
    Image preview(const Image& rendered) const override {
        const Image img = linear_rgb(rendered);
        std::vector<float> lum;
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) {
                float l = luminance(img.rgb_at(x, y));
                if (l > 0.0f && std::isfinite(l)) lum.push_back(l);
            }
        float top = max_value_;
        if (top <= 0.0f) {
            if (lum.empty())
                top = 1.0f;
            else {
                std::nth_element(lum.begin(), lum.begin() + long(0.99 * double(lum.size() - 1)), lum.end());
                top = lum[size_t(0.99 * double(lum.size() - 1))];
            }
        }
        Image map = Image::rgb(img.width(), img.height());
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) map.set_rgb(x, y, draw::colormap_sequential(luminance(img.rgb_at(x, y)) / top));
        std::vector<std::string> labels;
        for (int i = 4; i >= 0; --i) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.3g", double(top) * i / 4.0);
            labels.push_back(buf);
        }
        return draw::with_legend(map, draw::colormap_sequential, false, labels, "IRRADIANCE W/M^2");
    }

    std::string to_string() const override { return "irradiance"; }

private:
    PathIntegrator path_;
    float max_value_ = 0.0f;
};

CANDELA_REGISTER_SPECTRAL(IrradianceIntegrator, ObjectKind::Integrator, "irradiance");

}  // namespace candela
