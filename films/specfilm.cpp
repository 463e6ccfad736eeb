// specfilm: the spectral film (Mitsuba 3's specfilm): one channel per sensor response function
// (SRF), each the integral of srf(l) L(l) dl over 360-830 nm, the range Candela's spectra are
// defined on (no CIE normalisation, no colour conversion). Written as OpenEXR with the channels
// in alphabetical order of their names (as Mitsuba orders them), then the integrator's channels;
// no alpha. Renders only in the spectral variants (scalar_rgb stops at the film, as Mitsuba's
// RGB variants do).
//
// Parameters (Mitsuba 3 names and defaults):
//   width, height, crop_*, component_format, sample_border, banner, rfilter   as hdrfilm: see films/image_film.h
//   (any name)    spectrum   a sensor response function: its name is its channel's. At least
//                            one; values not negative; wavelength:value pairs, a .spd file, a
//                            regular or irregular spectrum, or one value (flat over 360-830 nm)
// Wavelengths are drawn in proportion to the sum of the responses (Mitsuba combines them into
// one distribution the same way), so every band gets samples where it responds; each sample's
// band j is (1/n) sum_i srf_j(l_i) L(l_i) / p(l_i) over its n wavelengths. A sensor's own `srf`
// and a specfilm exclude each other. Rendered by the integrators of the pixel loop (path,
// volpath, direct, photonmapper, ...); ptracer, sppm and raster, which develop images of their
// own, stop at the film, and so do what measures or shows a colour: --aov variance, adaptive
// sampling, --png.

#include "core/registry.h"
#include "core/texture.h"
#include "films/image_film.h"

#include <map>

namespace candela {

class SpecFilm final : public ImageFilm {
public:
    explicit SpecFilm(const Properties& props) : ImageFilm(props) {
        if (props.variant() == Variant::ScalarRGB)
            props.fail(
                "specfilm renders in the spectral variants only (--variant scalar_spectral), as Mitsuba's; "
                "in RGB use hdrfilm");
        std::map<std::string, SampledSpectrum> bands;  // by name: the channels' alphabetical order
        for (const std::string& name : props.names()) {
            auto measured = props.measured_spectrum(name);
            if (!measured) continue;  // another parameter (or a mistake check_all_used reports)
            props.get_texture(name);  // read: it is the band below
            if (name.rfind("_arg", 0) == 0) props.fail(name, "a specfilm's spectrum needs a name: it names the band's channel");
            // Part files list the bands joined by commas (SampleLayout::film_key).
            if (name.find_first_of(", \t\n") != std::string::npos)
                props.fail(name, "a band's name names its channel: no commas or spaces (\"" + name + "\")");
            const SampledSpectrum& response = measured->spectrum();
            for (double v : response.values)
                if (v < 0.0) props.fail(name, "a sensor response must not be negative (" + std::to_string(v) + ")");
            if (int(bands.size()) == MaxFilmBands) props.fail(name, "specfilm takes at most " + std::to_string(MaxFilmBands) + " bands");
            bands.emplace(name, response);
        }
        if (bands.empty())
            props.fail("specfilm needs at least one sensor response function: a <spectrum> with a name, which names its channel");
        std::vector<std::string> names;
        std::vector<SampledSpectrum> responses;
        for (auto& [name, response] : bands) {
            names.push_back(name);
            responses.push_back(std::move(response));
        }
        try {
            bands_ = std::make_unique<FilmBands>(std::move(names), std::move(responses));
        } catch (const SpectrumFormatError& e) {
            props.fail(std::string("specfilm's sensor responses: ") + e.what());
        }
    }

    // Not used: the bands replace the pixel format's channels.
    PixelFormat pixel_format() const override { return PixelFormat::RGB; }
    const FilmBands* bands() const override { return bands_.get(); }
    std::string to_string() const override { return "specfilm"; }

private:
    std::unique_ptr<FilmBands> bands_;
};

CANDELA_REGISTER(SpecFilm, ObjectKind::Film, "specfilm");

}  // namespace candela
