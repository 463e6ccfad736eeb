// stokes: the polarisation state the sensor measures, as a Stokes vector (Mitsuba 3's `stokes`).
// Renders only in scalar_spectral_polarized (elsewhere an input error, as in Mitsuba).
//
// Parameters (Mitsuba 3):
//   (nested integrator)   exactly one sampling integrator (path, volpath, direct, ...), whose
//                         image the film's own channels carry; its channels follow the Stokes ones
//   hide_emitters         boolean   read and ignored, as for every Mitsuba sampling integrator
// Channels S0.R, S0.G, S0.B, S1.R, ..., S3.B: the Stokes vector of each sample in linear sRGB
// (each component's spectrum through CIE 1931 as the film's radiance), in the sensor's frame:
// its basis is the camera's horizontal, d x up (d the ray direction, up the camera's y axis),
// the light observed from the sensor looking back along the beam. S0 is the radiance; S1 > 0
// where light is polarised horizontally, S2 > 0 at +45 degrees, S3 > 0 for right-circular.

#include "core/mueller.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/wavelengths.h"
#include "integrators/nested.h"

namespace candela {

class StokesIntegrator final : public SamplingIntegrator {
public:
    explicit StokesIntegrator(const Properties& props) {
        props.get_bool("hide_emitters", false);
        if (props.variant() != Variant::ScalarSpectralPolarized)
            props.fail(std::string("stokes renders only in variant scalar_spectral_polarized (--variant scalar_spectral_polarized); "
                                   "this render's variant is ") +
                       variant_name(props.variant()));
        std::vector<NestedIntegrator> nested = read_nested_integrators(props);
        if (nested.size() != 1) props.fail("stokes needs exactly one nested integrator (it has " + std::to_string(nested.size()) + ")");
        nested_ = std::move(nested[0]);
        for (int i = 0; i < 4; ++i)
            for (const char* c : {".R", ".G", ".B"}) names_.push_back("S" + std::to_string(i) + c);
        for (const std::string& c : nested_.channels) names_.push_back(c);
        if (names_.size() > size_t(MaxSampleChannels))
            props.fail("stokes and its nested integrator need " + std::to_string(names_.size()) + " channels, more than the " +
                       std::to_string(MaxSampleChannels) + " Candela supports");
    }

    void prepare(const Scene& scene) override { nested_.integrator->prepare(scene); }
    bool renders_media() const override { return nested_.integrator->renders_media(); }
    std::vector<std::string> channel_names() const override { return names_; }

    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const override {
        Wavelengths& wavelengths = *ray.wavelengths;  // the polarized variant always has them
        StokesSpectrum& sum = *wavelengths.stokes;
        sum = StokesSpectrum();
        SampleRecord inner;
        const Spectrum L = sample_nested(nested_, scene, sampler, ray, record, inner, true);
        record.valid = inner.valid;
        // From the implicit basis of the arriving light to the sensor's horizontal.
        const Vec3 up = scene.sensor().to_world().apply_vector(Vec3(0, 1, 0));
        const Vec3 horizontal = glm::cross(ray.d, up);
        const float length = glm::length(horizontal);
        const Mueller R = length > 0.0f ? rotate_stokes_basis(-ray.d, stokes_basis(-ray.d), horizontal / length) : Mueller::identity();
        StokesSpectrum measured;
        for (int k = 0; k < 3; ++k) measured.w[k] = R * sum.w[k];
        const SensorResponse* response = scene.sensor().response();
        for (int i = 0; i < 4; ++i) {
            Spectrum s = measured.component(i);
            if (response) s *= response->at(wavelengths);
            const Spectrum rgb = spectral_to_linear_srgb(s, wavelengths);
            for (int c = 0; c < 3; ++c) record.channels[3 * i + c] = rgb[c];
        }
        for (size_t c = 0; c < nested_.channels.size(); ++c) record.channels[12 + c] = inner.channels[c];
        return L;
    }

    std::string to_string() const override { return "stokes"; }

private:
    NestedIntegrator nested_;
    std::vector<std::string> names_;
};

CANDELA_REGISTER_SPECTRAL(StokesIntegrator, ObjectKind::Integrator, "stokes");

}  // namespace candela
