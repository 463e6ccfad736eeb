// constvolume: one value everywhere in its unit cube (Mitsuba 3's `constvolume`).
//
// Parameters:
//   value      float, rgb, spectrum, or a string of six numbers
//                             the value (default 1); in scalar_spectral an rgb is upsampled for
//                             the role of the medium parameter it serves (an albedo as a
//                             reflectance, sigma_t unbounded) and a measured <spectrum> is used
//                             per wavelength. Six numbers "S_xx, S_yy, S_zz, S_xy, S_xz,
//                             S_yz" give the symmetric matrix of an `sggx` phase function (the
//                             form of Mitsuba 2's constvolume and of Mitsuba's sggx tests; Mitsuba
//                             3 itself takes six values only from a gridvolume)
//   to_world   transform      places the unit cube [0, 1]^3 (default identity); it bounds a
//                             heterogeneous medium whose sigma_t is this volume, as in Mitsuba

#include "core/registry.h"
#include "core/text.h"
#include "core/texture.h"
#include "core/volume.h"

namespace candela {

class ConstVolume : public Volume {
public:
    explicit ConstVolume(const Properties& props) : Volume(props) {
        Properties::Type type = Properties::Type::Float;
        if (props.has("value")) props.get_raw("value", &type);
        if (type == Properties::Type::String) {
            read_numbers(props);
        } else {
            value_ = props.get_rgb("value", Spectrum(1.0f));
            if (!all_finite(value_)) props.fail("value", "the value must be finite");
            for (int k = 0; k < 3; ++k) values_[k] = value_[k];
            measured_ = props.measured_spectrum("value");
            if (measured_)
                for (double v : measured_->spectrum().values)
                    if (v < 0.0) props.fail("value", "constvolume: a measured spectrum must not be negative");
        }
        for (SpectrumRole role : {SpectrumRole::Reflectance, SpectrumRole::Unbounded, SpectrumRole::Emission})
            spectra_[int(role)] = RGBSpectrum(value_, role);
    }
    Spectrum eval(const Vec3&) const override { return value_; }
    void eval_channels(const Vec3&, float* out) const override { max_channels(out); }
    void max_channels(float* out) const override {
        for (int k = 0; k < channels_; ++k) out[k] = values_[k];
    }
    Spectrum max_in_local_box(const Vec3&, const Vec3&) const override { return value_; }
    Spectrum eval_spectrum(const Vec3&, const Wavelengths& w, SpectrumRole role) const override {
        return measured_ ? measured_->eval_spectrum(SurfaceInteraction(), w, role) : spectra_[int(role)].at(w);
    }
    float max_spectrum_in_local_box(const Vec3& lo, const Vec3& hi) const override {
        // A measured spectrum is linearly interpolated between its samples and zero beyond them:
        // its largest sample bounds it.
        if (!measured_) {
            // A grey value is the flat spectrum of itself.
            if (value_.x == value_.y && value_.y == value_.z) return std::max(value_.x, 0.0f);
            return Volume::max_spectrum_in_local_box(lo, hi);
        }
        double m = 0.0;
        for (double v : measured_->spectrum().values) m = std::max(m, v);
        return float(m);
    }
    bool is_constant() const override { return true; }
    std::string to_string() const override { return "constvolume"; }

private:
    // A string value: one, three or six numbers.
    void read_numbers(const Properties& props) {
        std::vector<std::string> items = split_list(props.get_string("value"));
        if (items.size() != 1 && items.size() != 3 && items.size() != 6)
            props.fail("value", "constvolume: a value of " + std::to_string(items.size()) + " numbers (1, 3 or 6 are meant)");
        channels_ = int(items.size());
        for (size_t k = 0; k < items.size(); ++k)
            if (!parse_finite_float(items[k], values_[k])) props.fail("value", "constvolume: \"" + items[k] + "\" is not a finite number");
        value_ = channels_ == 1 ? Spectrum(values_[0]) : Spectrum(values_[0], values_[1], values_[2]);
    }

    Spectrum value_;
    float values_[6] = {};
    RGBSpectrum spectra_[3];                           // value_'s spectrum for each SpectrumRole
    std::shared_ptr<const SpectrumTexture> measured_;  // the spectral variant's measured value
};

CANDELA_REGISTER_SPECTRAL(ConstVolume, ObjectKind::Volume, "constvolume");

}  // namespace candela
