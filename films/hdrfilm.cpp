// hdrfilm: the high dynamic range film, written as OpenEXR.
//
// Parameters (Mitsuba 3 names and defaults):
//   width, height         integer   film size in pixels (768 x 576)
//   crop_offset_x/_y      integer   top-left corner of the rendered window (0, 0)
//   crop_width/_height    integer   size of the rendered window (the whole film)
//   component_format      string    "float16" (default) or "float32"
//   pixel_format          string    "rgb" (the only supported format)
//   file_format           string    "openexr" (the only supported format)
//   sample_border         boolean   accepted for compatibility; must be false
//   rfilter               nested    reconstruction filter (default: gaussian)

#include "core/film.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class HDRFilm final : public Film {
public:
    explicit HDRFilm(const Properties& props) : location_(props.location()) {
        size_ = Vec2i(props.get_int("width", 768), props.get_int("height", 576));
        if (size_.x <= 0 || size_.y <= 0) props.fail("width", "film width and height must be positive");
        crop_offset_ = Vec2i(props.get_int("crop_offset_x", 0), props.get_int("crop_offset_y", 0));
        crop_size_ = Vec2i(props.get_int("crop_width", size_.x - crop_offset_.x), props.get_int("crop_height", size_.y - crop_offset_.y));
        if (crop_offset_.x < 0 || crop_offset_.y < 0 || crop_size_.x <= 0 || crop_size_.y <= 0 ||
            crop_offset_.x + crop_size_.x > size_.x || crop_offset_.y + crop_size_.y > size_.y)
            props.fail("crop window lies outside the film");
        std::string format = props.get_string("component_format", "float16");
        if (format != "float16" && format != "float32")
            props.fail("component_format", "component_format must be float16 or float32, not \"" + format + "\"");
        float32_ = format == "float32";
        std::string pixel_format = props.get_string("pixel_format", "rgb");
        if (pixel_format != "rgb") props.fail("pixel_format", "pixel_format \"" + pixel_format + "\" is not supported (use rgb)");
        std::string file_format = props.get_string("file_format", "openexr");
        if (file_format != "openexr" && file_format != "exr")
            props.fail("file_format", "file_format \"" + file_format + "\" is not supported (use openexr)");
        if (props.get_bool("sample_border", false)) props.fail("sample_border", "sample_border=true is not supported");

        auto filters = props.get_objects(ObjectKind::Filter);
        if (filters.size() > 1) props.fail("a film can have only one rfilter");
        filter_ = filters.empty() ? create_plugin_as<ReconstructionFilter>(ObjectKind::Filter, Properties("gaussian", props.location()))
                                  : std::static_pointer_cast<ReconstructionFilter>(filters[0]);
    }

    Vec2i full_size() const override { return size_; }
    Vec2i crop_offset() const override { return crop_offset_; }
    Vec2i crop_size() const override { return crop_size_; }
    const ReconstructionFilter& filter() const override { return *filter_; }
    bool float32() const override { return float32_; }
    SourceLocation location() const override { return location_; }

private:
    SourceLocation location_;
    Vec2i size_, crop_offset_, crop_size_;
    bool float32_ = false;
    Ref<ReconstructionFilter> filter_;
};

CANDELA_REGISTER(HDRFilm, ObjectKind::Film, "hdrfilm");

}  // namespace candela
