#include "sensors/projective.h"

#include "core/properties.h"
#include "core/registry.h"

namespace candela {

ProjectiveCamera::ProjectiveCamera(const Properties& props) {
    to_world_ = props.get_transform("to_world", Transform());
    auto films = props.get_objects(ObjectKind::Film);
    auto samplers = props.get_objects(ObjectKind::Sampler);
    if (films.size() > 1 || samplers.size() > 1) props.fail("a sensor has at most one film and one sampler");
    film_ = films.empty() ? create_plugin_as<Film>(ObjectKind::Film, Properties("hdrfilm", props.location()))
                          : std::static_pointer_cast<Film>(films[0]);
    sampler_ = samplers.empty() ? create_plugin_as<Sampler>(ObjectKind::Sampler, Properties("independent", props.location()))
                                : std::static_pointer_cast<Sampler>(samplers[0]);
    Vec2i size = film_->full_size();
    aspect_ = float(size.x) / float(size.y);
    inv_size_ = Vec2(1.0f / float(size.x), 1.0f / float(size.y));

    near_clip_ = props.get_float("near_clip", 0.01f);
    far_clip_ = props.get_float("far_clip", 10000.0f);
    if (!(near_clip_ > 0.0f)) props.fail("near_clip", "near_clip must be greater than zero");
    if (!(far_clip_ > near_clip_)) props.fail("far_clip", "far_clip must be greater than near_clip");
    focus_distance_ = props.get_float("focus_distance", far_clip_);
    if (!(focus_distance_ > 0.0f)) props.fail("focus_distance", "focus_distance must be positive");

    float open = props.get_float("shutter_open", 0.0f), close = props.get_float("shutter_close", 0.0f);
    if (!(close >= open)) props.fail("shutter_close", "shutter_open must not come after shutter_close");
    if (props.has("srf"))
        props.fail("srf", "a sensor response function (srf) needs a spectral variant; Candela renders in RGB, where Mitsuba rejects it too");
}

}  // namespace candela
