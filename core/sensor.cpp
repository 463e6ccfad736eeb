#include "core/sensor.h"

#include "core/error.h"
#include "core/medium.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"

#include <cmath>

namespace candela {

Sensor::Sensor(const Properties& props) {
    float open = props.get_float("shutter_open", 0.0f), close = props.get_float("shutter_close", 0.0f);
    if (!(close >= open)) props.fail("shutter_close", "shutter_open must not come after shutter_close");
    shutter_open_ = open;
    shutter_open_time_ = close - open;
    auto media = props.get_objects(ObjectKind::Medium);
    if (media.size() > 1) props.fail("a sensor stands in at most one medium");
    if (!media.empty()) medium_ = std::static_pointer_cast<Medium>(media[0]);
    auto films = props.get_objects(ObjectKind::Film);
    auto samplers = props.get_objects(ObjectKind::Sampler);
    if (films.size() > 1 || samplers.size() > 1) props.fail("a sensor has at most one film and one sampler");
    film_ = films.empty() ? create_plugin_as<Film>(ObjectKind::Film, Properties("hdrfilm", props.location()))
                          : std::static_pointer_cast<Film>(films[0]);
    set_sampler(samplers.empty() ? create_plugin_as<Sampler>(ObjectKind::Sampler, Properties(DefaultSampler, props.location()))
                                 : std::static_pointer_cast<Sampler>(samplers[0]));
    if (props.has("srf")) {
        if (props.variant() == Variant::ScalarRGB)
            props.fail("srf",
                       "a sensor response function (srf) needs a spectral variant (--variant scalar_spectral); Mitsuba's RGB "
                       "variants reject it too");
        if (film_->bands())
            props.fail("srf", "a sensor's srf and a specfilm's bands both weigh the wavelengths: give the responses to the specfilm alone");
        auto measured = props.measured_spectrum("srf");
        if (!measured) props.fail("srf", "srf must be a spectrum of samples (wavelength:value pairs, a file, regular or irregular)");
        props.get_texture("srf");  // read: it is the response below
        try {
            response_ = std::make_shared<SensorResponse>(measured->spectrum());
        } catch (const SpectrumFormatError& e) {
            props.fail("srf", e.what());
        }
    }
}

void Sensor::attach_to_shape(const Shape&, const Properties& shape_props) {
    shape_props.fail("the " + to_string() + " sensor cannot be nested in a shape (only an irradiancemeter can: it measures on its shape)");
}

void Sensor::set_film_size(const Vec2i&) { throw InputError("the " + to_string() + " sensor cannot take a slice of a batch's film"); }

float read_tan_half_fov_x(const Properties& props, float aspect) {
    float fov;
    std::string axis = "diagonal";
    if (props.has("fov")) {
        if (props.has("focal_length")) props.fail("focal_length", "give either fov or focal_length, not both");
        fov = props.get_float("fov");
        if (!(fov > 0.0f && fov < 180.0f)) props.fail("fov", "fov must be in (0, 180) degrees");
        axis = props.get_string("fov_axis", "x");
    } else {
        if (props.has("fov_axis"))
            props.fail("fov_axis", "fov_axis applies to fov only (a focal_length always spans the diagonal, as in Mitsuba)");
        std::string f = props.get_string("focal_length", "50mm");
        float mm = 0.0f;
        try {
            size_t used = 0;
            mm = std::stof(f, &used);
            std::string unit = f.substr(used);
            if (!(unit.empty() || unit == "mm")) throw std::invalid_argument(f);
        } catch (const std::exception&) {
            props.fail("focal_length", "focal_length must look like \"50mm\", not \"" + f + "\"");
        }
        if (!(mm > 0.0f)) props.fail("focal_length", "focal_length must be positive");
        // The 35 mm frame's diagonal (36 x 24 mm) fixes the diagonal field of view.
        fov = degrees(2.0f * std::atan(std::sqrt(36.0f * 36.0f + 24.0f * 24.0f) / (2.0f * mm)));
    }
    float t = std::tan(radians(fov) * 0.5f);
    if (axis == "smaller") axis = aspect > 1.0f ? "y" : "x";
    if (axis == "larger") axis = aspect > 1.0f ? "x" : "y";
    float tan_half_x = 0.0f;
    if (axis == "x")
        tan_half_x = t;
    else if (axis == "y")
        tan_half_x = t * aspect;
    else if (axis == "diagonal")
        tan_half_x = t * aspect / std::sqrt(1.0f + aspect * aspect);
    else
        props.fail("fov_axis", "fov_axis must be x, y, diagonal, smaller or larger, not \"" + axis + "\"");
    if (!(tan_half_x > 0.0f && std::isfinite(tan_half_x))) props.fail("fov", "the horizontal field of view must be in (0, 180) degrees");
    return tan_half_x;
}

}  // namespace candela
