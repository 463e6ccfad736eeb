// raster: renders the scene with a software rasterizer and the local illumination model of the
// lecture (what OpenGL's fixed-function pipeline computes), for side-by-side comparison with
// global illumination. Selected by <integrator type="raster"> or `candela render --mode raster`.
//
// Parameters (all optional; those marked * are also options of `candela render --mode raster`
// and `candela compare-modes`, with dashes: --aa-filter for aa_filter; raster_options() below is
// the table both read):
//   shading *              string    flat, gouraud or phong (default phong)
//   reflection *           string    phong (R.V lobe) or blinn (N.H lobe) (default blinn)
//   shadows *              string    none, map (shadow maps) or volume (shadow volumes)
//                                    (default map)
//   aa *                   integer   supersamples per pixel, >= 1 (default 1)
//   aa_filter *            string    box (coverage average), tent or gaussian (default box)
//   texture_filter *       string    nearest, bilinear or trilinear (MIP-mapped) (default trilinear)
//   wireframe *            boolean   draw visible triangle edges over the image (default false)
//   light_gizmos *         boolean   draw the lights: circles, spot axes, directional arrows
//                                    (default false)
//   affine *               boolean   interpolate in screen space, not perspective-correct
//                                    (default false)
//   backface_culling *     boolean   skip triangles facing away (unless two-sided) (default false)
//   ambient                rgb       extra ambient radiance added to the environments' (default 0)
//   environment_mapping *  string    latlong (look the environment up directly) or cube
//                                    (default latlong)
//   cube_map               string    six face images instead, "{face}" = px, nx, py, ny, pz, nz,
//                                    relative to the scene file (implies cube); radiance as
//                                    envmap reads it (8- and 16-bit images sRGB-decoded)
//   cube_resolution        integer   faces built from the environment, >= 1 (default 256)
//   shadow_map_resolution  integer   texels per side, >= 16 (default: chosen from the view per
//                                    map face, a texel no larger than the camera's sample
//                                    spacing on what the face shadows, at most 1024)
//   pcf                    integer   percentage-closer filter width in texels, >= 1 (default 3)
//   displacement           boolean   move bump-mapped surfaces by their height field (default false)
//   subdivisions           integer   4^n refinement of displaced shapes, >= 0 (default 3)
//   tessellation           integer   segments per turn for spheres and disks, >= 8 (default 96)
//   ao *                   integer   ambient occlusion rays per sample, >= 0: ray-cast with
//                                    Embree from the G-buffer positions, cosine-weighted
//                                    (default 0: none)
//   ao_ray_length          float     reach of those rays, > 0 (default: half the radius of the
//                                    scene's bounding sphere, as the `ao` integrator)
//   environment_lighting * string    ibl (the environment's irradiance from 9 SH coefficients,
//                                    glossy reflections from maps prefiltered by roughness) or
//                                    average (its average radiance as a constant ambient)
//                                    (default ibl)
//   lighting *             string    local (the lighting equation below) or baked (irradiance
//                                    baked at the vertices of radiosity patches, which then
//                                    replace the tessellation: displacement does not apply)
//                                    (default local)
//   bake *                 string    radiosity (bake_radiosity) or path (the path tracer's
//                                    irradiance estimate at each patch) (default radiosity)
//   bake_samples *         integer   paths per patch when baking with path, >= 1 (default 256)
//   bake_patch_area        float     largest patch in m^2 (default: 1/500 of the scene's
//                                    surface area)
//
// The lighting equation, per light with irradiance E (on a surface facing it), direction L,
// view V and normal N, is OpenGL's with physically scaled coefficients:
//   L_o = emission + kd / pi AO E_ambient + mirror env(R) + transmission env(T)
//       + sum over lights of visibility * E * [ kd / pi max(N.L, 0)
//                                              + (N.L > 0) ks c_n lobe ]
// with lobe = max(N.H, 0)^n and c_n = (n + 8) / (8 pi) for Blinn-Phong, lobe = max(R.V, 0)^n and
// c_n = (n + 2) / (2 pi) for Phong. kd, ks, n, mirror and transmission come from each BSDF's
// local_shading() (core/local_model.h; documented in every BSDF file). Delta lights give E
// exactly as the path tracer computes it (falloff, attenuation); an area light acts as a point
// light at its centre with intensity L A cos(theta) (planar) or L A / 4 (other shapes), and its
// surface shows its radiance L. Environments light diffuse surfaces through E_ambient, their
// irradiance E(N) from nine SH coefficients (or pi times their average radiance), plus pi times
// the `ambient` setting, times the ambient occlusion AO (1 without `ao`); mirrors and refractions
// look them up (glossy ones in maps prefiltered by roughness). Baked lighting replaces
// kd / pi AO E_ambient and the lights' diffuse terms by kd / pi E_baked (pass_ambient.cpp).
// Flat shading lights each triangle once at its centroid with the face normal, Gouraud lights
// each vertex once and interpolates, Phong lights every sample with the interpolated normal (and
// the bump- or normal-mapped frame).
//
// A frame is rendered in passes (frame.h): geometry (the G-buffer), surfaces, ambient, lights
// and shadows, resolve, overlays; each in its own pass_*.cpp.

#include "integrators/raster/raster.h"

#include "core/error.h"
#include "core/memory_budget.h"
#include "core/parallel.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/text.h"
#include "core/warning.h"
#include "integrators/radiosity.h"
#include "integrators/raster/environment.h"
#include "integrators/raster/frame.h"

#include <tbb/task_arena.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>

namespace candela {

// ---- options ---------------------------------------------------------------------------------

const std::vector<RasterOption>& raster_options() {
    using S = RasterSettings;
    using K = RasterOption::Kind;
    static const std::vector<RasterOption> options = {
        {"shading",
         K::Choice,
         {"flat", "gouraud", "phong"},
         0,
         true,
         "where lighting is computed: per face, per vertex or per sample",
         [](S& s, int v, const std::string&) { s.shading = S::Shading(v); }},
        {"reflection",
         K::Choice,
         {"phong", "blinn"},
         0,
         true,
         "the highlight lobe: R.V (Phong) or N.H (Blinn-Phong)",
         [](S& s, int v, const std::string&) { s.reflection = S::Reflection(v); }},
        {"shadows",
         K::Choice,
         {"none", "map", "volume"},
         0,
         true,
         "no shadows, shadow maps or shadow volumes",
         [](S& s, int v, const std::string&) { s.shadows = S::Shadows(v); }},
        {"aa", K::Integer, {}, 1, true, "supersamples per pixel", [](S& s, int v, const std::string&) { s.aa = v; }},
        {"aa_filter",
         K::Choice,
         {"box", "tent", "gaussian"},
         0,
         true,
         "the filter that resolves the supersamples",
         [](S& s, int v, const std::string&) { s.aa_filter = S::AAFilter(v); }},
        {"texture_filter",
         K::Choice,
         {"nearest", "bilinear", "trilinear"},
         0,
         true,
         "texture lookups (trilinear: MIP-mapped)",
         [](S& s, int v, const std::string&) { s.texture_filter = TextureFilter(v); }},
        {"wireframe", K::Boolean, {}, 0, true, "draw the visible triangle edges", [](S& s, int v, const std::string&) { s.wireframe = v; }},
        {"light_gizmos", K::Boolean, {}, 0, true, "draw the lights", [](S& s, int v, const std::string&) { s.light_gizmos = v; }},
        {"affine",
         K::Boolean,
         {},
         0,
         true,
         "affine (not perspective-correct) interpolation",
         [](S& s, int v, const std::string&) { s.affine = v; }},
        {"backface_culling", K::Boolean, {}, 0, true, "cull back faces", [](S& s, int v, const std::string&) { s.backface_culling = v; }},
        {"environment_mapping",
         K::Choice,
         {"latlong", "cube"},
         0,
         true,
         "look the environment up directly or in a cube map",
         [](S& s, int v, const std::string&) { s.cube_mapping = v == 1; }},
        {"cube_map",
         K::FacePattern,
         {},
         0,
         false,
         "six cube-face images, {face} = px, nx, py, ny, pz, nz",
         [](S& s, int, const std::string& text) {
             s.cube_map = text;
             s.cube_mapping = true;
         }},
        {"cube_resolution",
         K::Integer,
         {},
         1,
         false,
         "texels per side of the cube faces",
         [](S& s, int v, const std::string&) { s.cube_resolution = v; }},
        {"shadow_map_resolution",
         K::Integer,
         {},
         16,
         false,
         "texels per side of the shadow maps",
         [](S& s, int v, const std::string&) { s.shadow_map_resolution = v; }},
        {"pcf", K::Integer, {}, 1, false, "percentage-closer filter width in texels", [](S& s, int v, const std::string&) { s.pcf = v; }},
        {"displacement",
         K::Boolean,
         {},
         0,
         false,
         "displace bump-mapped surfaces",
         [](S& s, int v, const std::string&) { s.displacement = v; }},
        {"subdivisions",
         K::Integer,
         {},
         0,
         false,
         "4^n refinement of displaced shapes",
         [](S& s, int v, const std::string&) { s.subdivisions = v; }},
        {"tessellation",
         K::Integer,
         {},
         8,
         false,
         "segments per turn of spheres and disks",
         [](S& s, int v, const std::string&) { s.tessellation = v; }},
        {"ao",
         K::Integer,
         {},
         0,
         true,
         "ambient occlusion rays per sample, ray-cast with Embree (0: none)",
         [](S& s, int v, const std::string&) { s.ao = v; }},
        {"ao_ray_length",
         K::Float,
         {},
         0,
         false,
         "reach of the ambient occlusion rays",
         [](S& s, int, const std::string& text) { s.ao_ray_length = std::stof(text); }},
        {"environment_lighting",
         K::Choice,
         {"ibl", "average"},
         0,
         true,
         "the environment as image-based light (SH irradiance, prefiltered glossy) or its average",
         [](S& s, int v, const std::string&) { s.environment_lighting = S::EnvironmentLighting(v); }},
        {"lighting",
         K::Choice,
         {"local", "baked"},
         0,
         true,
         "light the surfaces by the local model or by baked irradiance",
         [](S& s, int v, const std::string&) { s.lighting = S::Lighting(v); }},
        {"bake",
         K::Choice,
         {"radiosity", "path"},
         0,
         true,
         "what bakes the irradiance: radiosity or the path tracer",
         [](S& s, int v, const std::string&) { s.bake = S::BakeSource(v); }},
        {"bake_samples",
         K::Integer,
         {},
         1,
         true,
         "path-traced irradiance samples per patch when baking with path",
         [](S& s, int v, const std::string&) { s.bake_samples = v; }},
        {"bake_patch_area",
         K::Float,
         {},
         0,
         false,
         "largest baked patch in m^2",
         [](S& s, int, const std::string& text) { s.bake_patch_area = std::stof(text); }},
    };
    return options;
}

std::string RasterOption::accepted() const {
    switch (kind) {
        case Kind::Choice: {
            std::string out;
            for (const char* c : choices) out += (out.empty() ? "" : "|") + std::string(c);
            return out;
        }
        case Kind::Integer: return "integer >= " + std::to_string(minimum);
        case Kind::Boolean: return "true|false";
        case Kind::FacePattern: return "file pattern with {face}";
        case Kind::Float: return "number > 0";
    }
    return "";
}

namespace {

const RasterOption* find_option(const std::string& name) {
    for (const RasterOption& o : raster_options())
        if (name == o.name) return &o;
    return nullptr;
}

// The number a valid value stands for (see RasterOption::store); false with a message if invalid.
bool parse_option(const RasterOption& o, const std::string& value, int& number, std::string& error) {
    switch (o.kind) {
        case RasterOption::Kind::Choice:
            for (size_t i = 0; i < o.choices.size(); ++i)
                if (value == o.choices[i]) {
                    number = int(i);
                    return true;
                }
            error = std::string(o.name) + " must be one of";
            for (const char* c : o.choices) error += std::string(" ") + c;
            error += ", not \"" + value + "\"";
            return false;
        case RasterOption::Kind::Integer: {
            long long v = 0;
            if (!parse_integer(value, v) || v < o.minimum || v > std::numeric_limits<int>::max()) {
                error = std::string(o.name) + " must be an integer >= " + std::to_string(o.minimum);
                return false;
            }
            number = int(v);
            return true;
        }
        case RasterOption::Kind::Boolean:
            if (value != "true" && value != "false") {
                error = std::string(o.name) + " must be true or false";
                return false;
            }
            number = value == "true";
            return true;
        case RasterOption::Kind::FacePattern: return true;
        case RasterOption::Kind::Float: {
            char* end = nullptr;
            float v = std::strtof(value.c_str(), &end);
            if (value.empty() || *end || !(v > 0.0f) || !std::isfinite(v)) {
                error = std::string(o.name) + " must be a number > 0";
                return false;
            }
            return true;
        }
    }
    return false;
}

// The option's property as text for RasterSettings::set. A face pattern resolves relative to the
// scene file, and each of its six files must exist.
std::string property_text(const Properties& props, const RasterOption& o) {
    switch (o.kind) {
        case RasterOption::Kind::Choice: return props.get_string(o.name);
        case RasterOption::Kind::Integer: return std::to_string(props.get_int(o.name));
        case RasterOption::Kind::Boolean: return props.get_bool(o.name, false) ? "true" : "false";
        case RasterOption::Kind::Float: {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.9g", double(props.get_float(o.name)));
            return buf;
        }
        case RasterOption::Kind::FacePattern: break;
    }
    std::string pattern = props.get_path(o.name);
    if (pattern.find("{face}") == std::string::npos) props.fail(o.name, std::string(o.name) + " must contain {face}");
    for (int face = 0; face < 6; ++face) {
        std::string file = raster::EnvironmentLookup::face_file(pattern, face);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec)) props.fail(o.name, "file not found: " + file);
    }
    return pattern;
}

// Stops the frame before any buffer is allocated when its buffers cannot fit in memory: the
// per-sample G-buffer, surfaces and colours (FrameBuffers, and the lights pass's depths and
// stencil), the pixels with the overlay depth and write_exr's copies, one shadow map (six faces
// for a point light) and the environment's cube faces with their MIP levels.
void check_frame_memory(const Film& film, const RasterSettings& s) {
    const Vec2i crop = film.crop_size();
    const uint64_t pixels = uint64_t(crop.x) * uint64_t(crop.y);
    const uint64_t per_sample = sizeof(float) + sizeof(uint32_t) + sizeof(Vec3) + sizeof(raster::SurfaceSample) + sizeof(Spectrum) +
                                sizeof(float) + sizeof(uint8_t);
    const uint64_t per_pixel = 2 * sizeof(Spectrum) + 3 * sizeof(uint16_t) + sizeof(float);  // image, its copy and halves, overlay depth
    uint64_t bytes =
        saturating_add(saturating_mul(saturating_mul(pixels, uint64_t(std::max(s.aa, 1))), per_sample), saturating_mul(pixels, per_pixel));
    if (s.shadows == RasterSettings::Shadows::Map) {
        uint64_t texels = saturating_mul(uint64_t(s.shadow_map_resolution), uint64_t(s.shadow_map_resolution));
        bytes = saturating_add(bytes, saturating_mul(texels, 6 * sizeof(float)));
    }
    if (s.cube_mapping) {
        uint64_t texels = saturating_mul(uint64_t(s.cube_resolution), uint64_t(s.cube_resolution));
        bytes = saturating_add(bytes, saturating_mul(texels, 6 * sizeof(Spectrum) * 4 / 3 + 1));
    }
    std::string what =
        film_description(film) + " rasterized with " + std::to_string(s.aa) + (s.aa == 1 ? " sample" : " samples") + " per pixel";
    check_memory(bytes, what, film.location());
}

}  // namespace

bool RasterSettings::set(const std::string& name, const std::string& value, std::string& error) {
    const RasterOption* option = find_option(name);
    if (!option) {
        error = "unknown raster option \"" + name + "\"";
        return false;
    }
    int number = 0;
    if (!parse_option(*option, value, number, error)) return false;
    option->store(*this, number, value);
    return true;
}

RasterIntegrator::RasterIntegrator(const Properties& props) {
    std::string error;
    for (const RasterOption& o : raster_options())
        if (props.has(o.name) && !settings_.set(o.name, property_text(props, o), error)) props.fail(o.name, error);
    settings_.ambient = props.get_rgb("ambient", Spectrum(0.0f));
}

// ---- rendering -------------------------------------------------------------------------------

namespace raster {

FrameSetup::FrameSetup(const Scene& scene, const RasterSettings& settings, const RasterGeometry& geometry, const PinholeProjection& pinhole,
                       const ImageBasedLighting* image_lighting)
    : scene(scene),
      settings(settings),
      geometry(geometry),
      camera(RasterCamera::from_pinhole(pinhole)),
      lights(collect_lights(scene)),
      ambient(lights.ambient + settings.ambient),
      image_lighting(image_lighting),
      full(scene.sensor().film().full_size()),
      offset(scene.sensor().film().crop_offset()),
      width(scene.sensor().film().crop_size().x),
      height(scene.sensor().film().crop_size().y),
      pattern(sample_pattern(settings.aa)) {}

float FrameSetup::sample_spacing(float view_depth) const {
    // A pixel spans 2 / (|P00| W) by 2 / (|P11| H) per unit of view depth (projection rows 0, 1).
    float per_depth =
        std::min(2.0f / (std::abs(camera.projection[0][0]) * float(full.x)), 2.0f / (std::abs(camera.projection[1][1]) * float(full.y)));
    return per_depth * view_depth / std::sqrt(float(samples_per_pixel()));
}

}  // namespace raster

RasterIntegrator::~RasterIntegrator() = default;

const raster::RasterGeometry& RasterIntegrator::geometry_for(const Scene& scene, const RenderOptions& options) {
    const RasterSettings& s = settings_;
    const bool baked = s.lighting == RasterSettings::Lighting::Baked;
    const std::array<double, 7> key = {double(s.tessellation),
                                       double(s.displacement),
                                       double(s.subdivisions),
                                       double(baked),
                                       baked ? double(s.bake) : 0.0,
                                       baked ? double(s.bake_samples) : 0.0,
                                       baked ? double(s.bake_patch_area) : 0.0};
    bake_seconds_ = 0.0;
    if (geometry_ && geometry_scene_ == &scene && key == geometry_key_) return *geometry_;
    if (baked) {
        // The bake replaces the tessellation: the patches, with the irradiance at their vertices.
        auto start = std::chrono::steady_clock::now();
        RadiositySettings bake;
        bake.max_patch_area = s.bake_patch_area;
        bake.default_area_fraction = 1.0f / 500.0f;  // coarser than radiosity's own: a bake is meant to be quick
        std::vector<RadiosityMesh> meshes = s.bake == RasterSettings::BakeSource::Radiosity
                                                ? bake_radiosity(scene, bake, options)
                                                : bake_path_irradiance(scene, bake, s.bake_samples, options);
        geometry_ = std::make_shared<raster::RasterGeometry>(raster::build_baked_geometry(meshes));
        bake_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } else {
        geometry_ = std::make_shared<raster::RasterGeometry>(raster::build_geometry(scene, s.tessellation, s.displacement, s.subdivisions));
    }
    geometry_scene_ = &scene;
    geometry_key_ = key;
    return *geometry_;
}

const raster::ImageBasedLighting* RasterIntegrator::image_lighting_for(const Scene& scene) {
    if (settings_.environment_lighting != RasterSettings::EnvironmentLighting::ImageBased || scene.infinite_emitters().empty())
        return nullptr;
    if (!image_lighting_ || image_lighting_scene_ != &scene) {
        image_lighting_ = std::make_shared<raster::ImageBasedLighting>(scene);
        image_lighting_scene_ = &scene;
    }
    return image_lighting_.get();
}

namespace {

// The resolved frame in the film's pixel format, its coverage as the alpha.
Image in_pixel_format(const Image& rgb, const std::vector<float>& coverage, PixelFormat format) {
    if (format == PixelFormat::RGB) return rgb;
    Image out(rgb.width(), rgb.height(), pixel_format_channels(format));
    for (int y = 0; y < rgb.height(); ++y)
        for (int x = 0; x < rgb.width(); ++x)
            write_pixel_format(format, rgb.rgb_at(x, y), coverage[size_t(y) * rgb.width() + x], &out.at(x, y, 0));
    return out;
}

// Blacks out the pixels whose colour is not storable (NaN, infinite or beyond 1e30: core/film.h),
// as the pixel loop drops such samples; how many. Finite inputs can still overflow float in a
// frame's sums (an intensity near 3.4e38 times a falloff and a sum of lights).
uint64_t drop_unstorable_pixels(Image& rgb) {
    uint64_t dropped = 0;
    for (int y = 0; y < rgb.height(); ++y)
        for (int x = 0; x < rgb.width(); ++x)
            if (!storable_sample_value(rgb.rgb_at(x, y))) {
                for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = 0.0f;
                ++dropped;
            }
    return dropped;
}

}  // namespace

RenderResult RasterIntegrator::render(const Scene& scene, const RenderOptions& options) {
    using namespace raster;
    refuse_film_bands(scene);
    for (const auto& shape : scene.shapes())
        if (shape->is_medium_transition()) {
            warn(SourceLocation{scene.source_file, 0},
                 "the raster mode draws only the medium around the camera, as fog; media inside shapes are left out");
            break;
        }
    if (scene.is_animated())
        warn(SourceLocation{scene.source_file, 0}, "the raster mode draws one instant, the pose at shutter_open: no motion blur");
    auto t_start = std::chrono::steady_clock::now();
    if (!options.aovs.empty())
        throw InputError("the raster mode renders no AOVs (albedo, normal, depth, variance come from sampling integrators)");
    auto pinhole = scene.sensor().pinhole();
    if (!pinhole) throw InputError("the raster mode needs a perspective (pinhole) camera");
    check_frame_memory(scene.sensor().film(), settings_);
    tbb::task_arena arena = thread_arena(options.threads);
    RenderResult result;
    arena.execute([&] {
        FrameSetup frame(scene, settings_, geometry_for(scene, options), *pinhole, image_lighting_for(scene));
        if (!buffers_) buffers_ = std::make_shared<FrameBuffers>();
        FrameBuffers& buffers = *buffers_;
        geometry_pass(frame, buffers);
        surface_pass(frame, buffers);
        ambient_pass(frame, buffers);
        lights_pass(frame, buffers);
        fog_pass(frame, buffers);
        resolve_pass(frame, buffers);
        overlay_pass(frame, buffers);
        result.stats.nonfinite = drop_unstorable_pixels(buffers.image);
        result.image = in_pixel_format(buffers.image, buffers.coverage, scene.sensor().film().pixel_format());
        result.stats.samples = frame.sample_count();
    });
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    result.stats.spp = settings_.aa;
    result.stats.single_frame = true;
    return result;
}

CANDELA_REGISTER(RasterIntegrator, ObjectKind::Integrator, "raster");

}  // namespace candela
