#pragma once
// The rasterized local-illumination mode (see raster.cpp for the parameters).

#include "core/integrator.h"
#include "core/texture.h"

#include <memory>
#include <string>
#include <vector>

namespace candela {

namespace raster {
struct RasterGeometry;
}

struct RasterSettings {
    enum class Shading { Flat, Gouraud, Phong };
    enum class Reflection { Phong, Blinn };
    enum class Shadows { None, Map, Volume };
    enum class AAFilter { Box, Tent, Gaussian };
    Shading shading = Shading::Phong;
    Reflection reflection = Reflection::Blinn;
    Shadows shadows = Shadows::Map;
    int aa = 1;
    AAFilter aa_filter = AAFilter::Box;
    TextureFilter texture_filter = TextureFilter::Trilinear;
    bool wireframe = false, light_gizmos = false, affine = false, backface_culling = false;
    Spectrum ambient{0.0f};
    bool cube_mapping = false;
    int cube_resolution = 256;
    std::string cube_map;  // six images, "{face}" replaced by px, nx, py, ny, pz, nz
    int shadow_map_resolution = 1024, pcf = 3;
    bool displacement = false;
    int subdivisions = 3, tessellation = 96;

    // Parses one named option ("shading", "aa", ...) from text; false, with a message in
    // `error`, for an unknown option or an invalid value.
    bool set(const std::string& name, const std::string& value, std::string& error);
};

// One option of the raster mode: a property of <integrator type="raster"> and, when
// `command_line`, an option of `candela render` and `compare-modes` (--aa-filter for aa_filter).
// raster_options() (raster.cpp) is the one list of them: RasterSettings::set parses by it, the
// integrator reads its properties by it, and the command line offers and documents them by it.
struct RasterOption {
    enum class Kind { Choice, Integer, Boolean, FacePattern };
    const char* name;
    Kind kind;
    std::vector<const char*> choices;  // Choice: the accepted values, in the order of the setting's enum
    int minimum;                       // Integer: the least accepted value
    bool command_line;
    const char* help;  // what it sets, in a few words
    // Stores a valid value: the index of the choice, the integer, 1 or 0 for true or false, or
    // the text itself (FacePattern: six file names, "{face}" standing for px, nx, py, ny, pz, nz).
    void (*store)(RasterSettings& settings, int number, const std::string& text);

    // The accepted values for help texts: "flat|gouraud|phong", "integer >= 1", "true|false".
    std::string accepted() const;
};
const std::vector<RasterOption>& raster_options();

class RasterIntegrator : public Integrator {
public:
    explicit RasterIntegrator(const class Properties& props);
    explicit RasterIntegrator(const RasterSettings& settings) : settings_(settings) {}
    ~RasterIntegrator() override;
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
    std::string to_string() const override { return "raster"; }

    RasterSettings& settings() { return settings_; }

private:
    // The tessellated scene for these settings, rebuilt only when the scene or the settings that
    // shape the geometry change.
    const raster::RasterGeometry& geometry_for(const Scene& scene);

    RasterSettings settings_;
    // The tessellated scene, kept between frames of the same scene and geometry settings.
    std::shared_ptr<raster::RasterGeometry> geometry_;
    const Scene* geometry_scene_ = nullptr;
    int geometry_key_[3] = {0, 0, 0};
};

}  // namespace candela
