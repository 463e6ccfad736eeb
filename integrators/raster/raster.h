#pragma once
// The rasterized local-illumination mode (see raster.cpp for the parameters).

#include "core/integrator.h"
#include "core/texture.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace candela {

namespace raster {
struct RasterGeometry;
struct FrameBuffers;
class ImageBasedLighting;
}  // namespace raster

struct RasterSettings {
    enum class Shading { Flat, Gouraud, Phong };
    enum class Reflection { Phong, Blinn };
    enum class Shadows { None, Map, Volume };
    enum class AAFilter { Box, Tent, Gaussian };
    enum class EnvironmentLighting { ImageBased, Average };
    enum class Lighting { Local, Baked };
    enum class BakeSource { Radiosity, Path };
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
    std::string cube_map;                    // six images, "{face}" replaced by px, nx, py, ny, pz, nz
    int shadow_map_resolution = 0, pcf = 3;  // resolution 0: chosen from the view
    bool displacement = false;
    int subdivisions = 3, tessellation = 96;
    // Approximations of global illumination (pass_ambient.cpp): ambient occlusion rays per
    // sample (0: none) and their reach (<= 0: half the scene's bounding radius, as `ao`); the
    // environment as image-based light (SH irradiance, prefiltered glossy) or its average
    // radiance; and baked lighting (irradiance precomputed at patch vertices).
    int ao = 0;
    float ao_ray_length = 0.0f;
    EnvironmentLighting environment_lighting = EnvironmentLighting::ImageBased;
    Lighting lighting = Lighting::Local;
    BakeSource bake = BakeSource::Radiosity;
    int bake_samples = 256;
    float bake_patch_area = 0.0f;  // 0: 1/500 of the scene's surface area

    // Parses one named option ("shading", "aa", ...) from text; false, with a message in
    // `error`, for an unknown option or an invalid value.
    bool set(const std::string& name, const std::string& value, std::string& error);
};

// One option of the raster mode: a property of <integrator type="raster"> and, when
// `command_line`, an option of `candela render` and `compare-modes` (--aa-filter for aa_filter).
// raster_options() (raster.cpp) is the one list of them: RasterSettings::set parses by it, the
// integrator reads its properties by it, and the command line offers and documents them by it.
struct RasterOption {
    enum class Kind { Choice, Integer, Boolean, FacePattern, Float };
    const char* name;
    Kind kind;
    std::vector<const char*> choices;  // Choice: the accepted values, in the order of the setting's enum
    int minimum;                       // Integer: the least accepted value (Float: any value > 0)
    bool command_line;
    const char* help;  // what it sets, in a few words
    // Stores a valid value: the index of the choice, the integer, 1 or 0 for true or false, or
    // the text itself (FacePattern: six file names, "{face}" standing for px, nx, py, ny, pz, nz;
    // Float: the number as text).
    void (*store)(RasterSettings& settings, int number, const std::string& text);

    // The accepted values for help texts: "flat|gouraud|phong", "integer >= 1", "true|false",
    // "number > 0".
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
    // The medium around the camera becomes exponential fog (pass_fog.cpp).
    bool renders_media() const override { return true; }

    RasterSettings& settings() { return settings_; }
    // Seconds spent baking the lighting for the last frame (0 when it was reused or not baked).
    double bake_seconds() const { return bake_seconds_; }

private:
    // The tessellated scene for these settings, rebuilt only when the scene or the settings that
    // shape the geometry change.
    const raster::RasterGeometry& geometry_for(const Scene& scene, const RenderOptions& options);
    // The environment's image-based lighting, computed once per scene (null without one).
    const raster::ImageBasedLighting* image_lighting_for(const Scene& scene);

    RasterSettings settings_;
    // The tessellated scene, kept between frames of the same scene and geometry settings.
    std::shared_ptr<raster::RasterGeometry> geometry_;
    const Scene* geometry_scene_ = nullptr;
    std::array<double, 7> geometry_key_{};  // what the geometry was built for (see geometry_for)
    std::shared_ptr<raster::ImageBasedLighting> image_lighting_;
    const Scene* image_lighting_scene_ = nullptr;
    double bake_seconds_ = 0.0;
    // The frame buffers and shadow maps, kept from frame to frame so that a frame of the same
    // size reuses their storage instead of allocating it.
    std::shared_ptr<raster::FrameBuffers> buffers_;
};

}  // namespace candela
