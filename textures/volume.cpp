// volume: a 3D texture on a surface (Mitsuba 3's `volume` texture): the value of a volume plugin
// (constvolume, gridvolume) at the surface point's world position, for surfaces without a
// useful uv parameterisation or for solid textures. The volume's own to_world places it.
//
// Parameters (Mitsuba 3):
//   volume   float, rgb or volume   the volume looked up (default 0.75); a float or rgb is a
//                                   constvolume of that value
//
// A surface point's value is the volume's there, in every variant (in the spectral variant at
// the path's wavelengths, as the volume gives them). The lookups that have no point take the
// volume's mean over its unit cube (an 8 x 8 x 8 grid of cell centres): the raster mode's
// texture filtering, albedo and power estimates, and bump mapping (whose gradient is taken in
// uv space, so a volume texture gives a bump map no slope).

#include "core/volume.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"

namespace candela {

class VolumeTexture final : public Texture {
public:
    explicit VolumeTexture(const Properties& props) : Texture(props), volume_(get_volume(props, "volume", Spectrum(0.75f))) {
        const int n = 8;
        Spectrum sum(0.0f);
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x)
                    sum += volume_->eval(volume_->to_world().apply_point((Vec3(float(x), float(y), float(z)) + 0.5f) / float(n)));
        mean_ = sum / float(n * n * n);
    }

    Spectrum eval(const Vec2&) const override { return mean_; }
    Spectrum eval_rgb(const SurfaceInteraction& si) const override { return volume_->eval(si.p); }
    // A grey volume's value exactly; a colour's luminance, as every texture's scalar view.
    float eval_1(const SurfaceInteraction& si) const override {
        const Spectrum v = volume_->eval(si.p);
        return volume_->channel_count() == 1 ? v.x : luminance(v);
    }
    Spectrum eval_spectrum(const SurfaceInteraction& si, const Wavelengths& w, SpectrumRole role) const override {
        return volume_->eval_spectrum(si.p, w, role);
    }
    Spectrum mean() const override { return mean_; }
    float max_value() const override { return max_component(volume_->max()); }

    void traverse(ParameterVisitor& visitor) override { visitor.object("volume", volume_.get()); }
    std::string to_string() const override { return "volume"; }

private:
    Ref<Volume> volume_;
    Spectrum mean_{0.0f};
};

CANDELA_REGISTER_SPECTRAL(VolumeTexture, ObjectKind::Texture, "volume");

}  // namespace candela
