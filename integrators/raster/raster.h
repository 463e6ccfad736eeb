#pragma once
// The rasterized local-illumination mode (see raster.cpp for the parameters).

#include "core/integrator.h"
#include "textures/mipmap.h"

#include <memory>
#include <string>

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

    // Parses one named option ("shading", "aa", ...) from text; false if the value is invalid.
    bool set(const std::string& name, const std::string& value, std::string& error);
};

class RasterIntegrator : public Integrator {
public:
    explicit RasterIntegrator(const class Properties& props);
    explicit RasterIntegrator(const RasterSettings& settings) : settings_(settings) {}
    ~RasterIntegrator() override;
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
    std::string to_string() const override { return "raster"; }

    RasterSettings& settings() { return settings_; }

private:
    RasterSettings settings_;
    // The tessellated scene, kept between frames of the same scene and geometry settings.
    std::shared_ptr<raster::RasterGeometry> geometry_;
    const Scene* geometry_scene_ = nullptr;
    int geometry_key_[3] = {0, 0, 0};
};

}  // namespace candela
