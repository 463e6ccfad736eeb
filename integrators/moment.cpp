// moment: the first and second moments of the samples of nested integrators (Mitsuba 3's
// `moment`), from which the variance of each pixel follows.
//
// Parameters (Mitsuba 3):
//   (nested integrators)   sampling integrators, each named by its name attribute; for each,
//                          in document order: its own channels as name.<channel>, then its
//                          radiance as CIE XYZ, name.X, name.Y, name.Z (from linear sRGB, as
//                          the film's xyz format converts). Then, for every one of those
//                          channels c, "m2_c": the same value squared, sample by sample.
//   hide_emitters          boolean   read and ignored, as for every Mitsuba sampling integrator
// The film's own channels carry the first nested integrator's image and valid flag. Both
// moments are filtered like the radiance: with a box filter, a pixel's c is the mean of its
// samples and m2_c the mean of their squares, so m2_c - c^2 is the variance of one sample
// (times (n - 1) / n: the sample variance with n - 1, divided by n).

#include "core/properties.h"
#include "core/registry.h"
#include "core/spectral.h"
#include "core/wavelengths.h"
#include "integrators/nested.h"

namespace candela {

class MomentIntegrator final : public SamplingIntegrator {
public:
    explicit MomentIntegrator(const Properties& props) : nested_(read_nested_integrators(props)) {
        props.get_bool("hide_emitters", false);
        for (const NestedIntegrator& n : nested_) {
            for (const std::string& c : n.channels) names_.push_back(n.name + "." + c);
            for (const char* c : {".X", ".Y", ".Z"}) names_.push_back(n.name + c);
        }
        size_t first_moments = names_.size();
        for (size_t i = 0; i < first_moments; ++i) names_.push_back("m2_" + names_[i]);
        if (names_.size() > size_t(MaxSampleChannels))
            props.fail("the nested integrators' moments need " + std::to_string(names_.size()) + " channels, more than the " +
                       std::to_string(MaxSampleChannels) + " Candela supports");
    }

    void prepare(const Scene& scene) override {
        for (const NestedIntegrator& n : nested_) n.integrator->prepare(scene);
    }

    std::vector<std::string> channel_names() const override { return names_; }

    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const override {
        Spectrum result(0.0f);
        const size_t first_moments = names_.size() / 2;
        float* out = record.channels;
        for (size_t i = 0; i < nested_.size(); ++i) {
            SampleRecord inner;
            Spectrum L = sample_nested(nested_[i], scene, sampler, ray, record, inner, i == 0);
            for (size_t c = 0; c < nested_[i].channels.size(); ++c) *out++ = inner.channels[c];
            // The sample's colour (in the spectral variant its values through CIE 1931), then XYZ.
            Vec3d xyz = linear_srgb_to_xyz(Vec3d(ray.wavelengths ? spectral_to_linear_srgb(L, *ray.wavelengths) : L));
            for (int k = 0; k < 3; ++k) *out++ = float(xyz[k]);
            if (i == 0) {
                result = L;
                record.valid = inner.valid;
            }
        }
        for (size_t c = 0; c < first_moments; ++c) record.channels[first_moments + c] = sqr(record.channels[c]);
        return result;
    }

    std::string to_string() const override { return "moment"; }

private:
    std::vector<NestedIntegrator> nested_;
    std::vector<std::string> names_;
};

CANDELA_REGISTER_SPECTRAL(MomentIntegrator, ObjectKind::Integrator, "moment");

}  // namespace candela
