// hdrfilm: the high dynamic range film, written as OpenEXR.
//
// Parameters (Mitsuba 3 names and defaults):
//   width, height         integer   film size in pixels (768 x 576)
//   crop_offset_x/_y      integer   top-left corner of the rendered window (0, 0)
//   crop_width/_height    integer   size of the rendered window (the whole film)
//   pixel_format          string    the film's channels (default rgb): luminance (Y),
//                                   luminance_alpha (Y, A), rgb (R, G, B), rgba (R, G, B, A),
//                                   xyz (X, Y, Z), xyza (X, Y, Z, A). XYZ and the luminance Y
//                                   are CIE 1931 from linear sRGB (Rec. 709, D65). A is the
//                                   filtered fraction of samples that saw something (each
//                                   integrator says what counts: for path a surface or a
//                                   visible environment); colour channels are not divided by it.
//   component_format      string    float16 (default) or float32; uint32 is refused
//   file_format           string    openexr (or exr; the default); rgbe and pfm are refused
//   sample_border         boolean   also sample the pixels just outside the crop window that
//                                   the filter reaches, so that edge pixels get their whole
//                                   filter support (default false; high_quality_edges is
//                                   Mitsuba 2's name for it)
//   banner                boolean   accepted and ignored, as in Mitsuba 3
//   rfilter               nested    reconstruction filter (default: gaussian)
// Names are case-insensitive, as in Mitsuba.

#include "core/film.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/text.h"

namespace candela {

namespace {

PixelFormat read_pixel_format(const Properties& props) {
    static const std::pair<const char*, PixelFormat> formats[] = {{"luminance", PixelFormat::Luminance},
                                                                  {"luminance_alpha", PixelFormat::LuminanceAlpha},
                                                                  {"rgb", PixelFormat::RGB},
                                                                  {"rgba", PixelFormat::RGBA},
                                                                  {"xyz", PixelFormat::XYZ},
                                                                  {"xyza", PixelFormat::XYZA}};
    std::string name = to_lower(props.get_string("pixel_format", "rgb"));
    for (const auto& [known, format] : formats)
        if (name == known) return format;
    props.fail("pixel_format", "pixel_format \"" + name + "\" is not one of luminance, luminance_alpha, rgb, rgba, xyz, xyza");
}

}  // namespace

class HDRFilm final : public Film {
public:
    explicit HDRFilm(const Properties& props) : location_(props.location()) {
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
        pixel_format_ = read_pixel_format(props);
        std::string file_format = to_lower(props.get_string("file_format", "openexr"));
        if (file_format != "openexr" && file_format != "exr")
            props.fail("file_format", "file_format \"" + file_format + "\" is not supported: Candela writes OpenEXR only (openexr)");
        if (props.has("sample_border") && props.has("high_quality_edges"))
            props.fail("high_quality_edges", "give sample_border or its old name high_quality_edges, not both");
        sample_border_ =
            props.has("high_quality_edges") ? props.get_bool("high_quality_edges", false) : props.get_bool("sample_border", false);
        props.get_bool("banner", false);  // no banner in Mitsuba 3 either

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
    PixelFormat pixel_format() const override { return pixel_format_; }
    bool sample_border() const override { return sample_border_; }
    SourceLocation location() const override { return location_; }

private:
    SourceLocation location_;
    Vec2i size_, crop_offset_, crop_size_;
    bool float32_ = false, sample_border_ = false;
    PixelFormat pixel_format_ = PixelFormat::RGB;
    Ref<ReconstructionFilter> filter_;
};

CANDELA_REGISTER(HDRFilm, ObjectKind::Film, "hdrfilm");

}  // namespace candela
