#include "films/image_film.h"

#include "core/registry.h"
#include "core/text.h"

namespace candela {

ImageFilm::ImageFilm(const Properties& props) : location_(props.location()) {
    size_ = Vec2i(props.get_int("width", 768), props.get_int("height", 576));
    if (size_.x <= 0 || size_.y <= 0) props.fail("width", "film width and height must be positive");
    crop_offset_ = Vec2i(props.get_int("crop_offset_x", 0), props.get_int("crop_offset_y", 0));
    crop_size_ = Vec2i(props.get_int("crop_width", size_.x - crop_offset_.x), props.get_int("crop_height", size_.y - crop_offset_.y));
    if (crop_offset_.x < 0 || crop_offset_.y < 0 || crop_size_.x <= 0 || crop_size_.y <= 0 || crop_offset_.x + crop_size_.x > size_.x ||
        crop_offset_.y + crop_size_.y > size_.y)
        props.fail("crop window lies outside the film");
    std::string format = to_lower(props.get_string("component_format", "float16"));
    if (format == "uint32") props.fail("component_format", "component_format uint32 is not supported (use float16 or float32)");
    if (format != "float16" && format != "float32")
        props.fail("component_format", "component_format must be float16 or float32, not \"" + format + "\"");
    float32_ = format == "float32";
    if (props.has("sample_border") && props.has("high_quality_edges"))
        props.fail("high_quality_edges", "give sample_border or its old name high_quality_edges, not both");
    sample_border_ = props.has("high_quality_edges") ? props.get_bool("high_quality_edges", false) : props.get_bool("sample_border", false);
    props.get_bool("banner", false);  // no banner in Mitsuba 3 either

    auto filters = props.get_objects(ObjectKind::Filter);
    if (filters.size() > 1) props.fail("a film can have only one rfilter");
    filter_ = filters.empty() ? create_plugin_as<ReconstructionFilter>(ObjectKind::Filter, Properties("gaussian", props.location()))
                              : std::static_pointer_cast<ReconstructionFilter>(filters[0]);
}

}  // namespace candela
