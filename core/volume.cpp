#include "core/volume.h"

#include "core/registry.h"
#include "core/texture.h"

namespace candela {

Volume::Volume(const Properties& props) {
    Transform to_world = props.get_transform("to_world", Transform());
    if (!to_world.all_finite() || to_world.determinant3() == 0.0f) props.fail("to_world", "the volume's to_world must be invertible");
    set_to_world(to_world);
}

void Volume::set_to_world(const Transform& to_world) {
    to_world_ = to_world;
    to_local_ = to_world.inverse();
    bbox_ = BoundingBox();
    for (int corner = 0; corner < 8; ++corner)
        bbox_.expand(to_world_.apply_point(Vec3(float(corner & 1), float((corner >> 1) & 1), float((corner >> 2) & 1))));
}

Spectrum Volume::eval_spectrum(const Vec3& p_world, const Wavelengths& w, SpectrumRole role) const {
    const Spectrum value = eval(p_world);
    // A grey value is the flat spectrum of itself (rgb_at_wavelengths would give the same for a
    // reflectance in [0, 1] or an unbounded value, without the table lookup).
    if (channels_ == 1 && role != SpectrumRole::Emission) return value;
    return rgb_at_wavelengths(value, role, &w);
}

float Volume::max_spectrum_in_local_box(const Vec3& lo, const Vec3& hi) const {
    // A trilinear lookup is a convex combination of voxels, so its largest channel is at most
    // the box's largest channel maximum.
    const float m = std::max(max_component(max_in_local_box(lo, hi)), 0.0f);
    return channels_ == 1 ? m : 2.0f * m;
}

Ref<Volume> get_volume(const Properties& props, const std::string& name, const Spectrum& def) {
    if (props.has(name)) {
        Properties::Type type;
        const Properties::Value& raw = props.get_raw(name, &type);
        if (type == Properties::Type::Object) {
            auto object = std::get<Ref<Object>>(raw);
            if (object && object->kind() == ObjectKind::Volume) {
                auto volume = std::static_pointer_cast<Volume>(object);
                if (volume->channel_count() == 6)
                    props.fail(name, "a volume of six channels holds a matrix (SGGX's S), not a value for \"" + name + "\"");
                return volume;
            }
        }
    }
    // A constant (float, rgb, or a <spectrum> constant texture), read as an rgb; in the spectral
    // variant a measured spectrum goes along, to be used per wavelength.
    Properties constant("constvolume", props.location_of(name));
    constant.set_variant(props.variant());
    if (auto measured = props.measured_spectrum(name))
        constant.set_object("value", std::const_pointer_cast<SpectrumTexture>(measured), props.location_of(name));
    else
        constant.set_rgb("value", props.get_rgb(name, def));
    return create_plugin_as<Volume>(ObjectKind::Volume, constant);
}

}  // namespace candela
