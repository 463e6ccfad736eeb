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

#include "core/registry.h"
#include "core/text.h"
#include "films/image_film.h"

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

class HDRFilm final : public ImageFilm {
public:
    explicit HDRFilm(const Properties& props) : ImageFilm(props) {
        pixel_format_ = read_pixel_format(props);
        std::string file_format = to_lower(props.get_string("file_format", "openexr"));
        if (file_format != "openexr" && file_format != "exr")
            props.fail("file_format", "file_format \"" + file_format + "\" is not supported: Candela writes OpenEXR only (openexr)");
    }

    PixelFormat pixel_format() const override { return pixel_format_; }
    std::string to_string() const override { return "hdrfilm"; }

private:
    PixelFormat pixel_format_ = PixelFormat::RGB;
};

CANDELA_REGISTER(HDRFilm, ObjectKind::Film, "hdrfilm");

}  // namespace candela
