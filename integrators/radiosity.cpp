// radiosity: diffuse global illumination by the radiosity method. The scene's surfaces (every
// shape through its tessellation) are cut into patches; progressive refinement (Cohen et al.
// 1988) shoots light from the patch with the most unshot power to all others, with form
// factors from an exact point-to-triangle formula times ray-cast visibility
// (radiosity_solver.cpp); the image shows the solution either smoothly interpolated between
// vertices or through a final gather.
//
// Parameters:
//   max_patch_area   float     largest patch in m^2 (default: 1/2000 of the scene's surface area)
//   subdivisions     integer   instead of max_patch_area: split every tessellated triangle into
//                              n x n patches
//   tolerance        float     stop when the unshot power is below this fraction of the emitted
//                              power (default 0.001)
//   max_iterations   integer   most shots (default 100000)
//   visibility_rays  integer   visibility rays per form factor (default 16)
//   seed             integer   seed of the visibility samples (default 0)
//   final_gather     boolean   true (default): at each camera hit, emission plus direct light
//                              by light sampling plus one bounce of gathering (a BSDF-sampled
//                              ray that reads the reflected radiosity where it lands); false:
//                              the interpolated radiosity / pi of the surface the camera sees
//   solution         string    a file (relative to the scene file) to reuse the solution from
//                              and to save it to; a file made for another scene or other
//                              settings is refused, solved again and replaced
//
// Light: area emitters shoot; point, spot, directional and environment emitters light the
// patches once before the first shot (their reflected light is then shot on). Materials: a
// non-diffuse BSDF is treated by its albedo (the run names those BSDFs in a warning); a two-sided
// one gets patches on both sides; a surface with only a null lobe (`null`) is left out. The final gather evaluates the real BSDF where the camera
// looks, so mirrors and glass show the solution in reflection. Radiosity renders the patches it
// solves on: analytic shapes appear as their tessellation. Ctrl-C during the solve stops it and
// shows the partial solution at one sample per pixel, marked partial.
//
// In scalar_spectral (and its polarized variant) the solve stays in RGB (emitters' and
// albedos' RGB values, one radiosity per patch for every view), and what the camera sees of it
// is that RGB radiance upsampled at the sample's wavelengths (an emission spectrum: RGB times
// D65, core/wavelengths.h). Emission, direct light and the gathered bounce's BSDF are evaluated
// at the wavelengths, so only light that has bounced once or more before the last surface
// passes through RGB (as a render of RGB inputs would, up to the upsampling's nonlinearity).

#include "integrators/radiosity.h"

#include "core/bsdf.h"
#include "core/emitter.h"
#include "core/mesh.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/spectral.h"
#include "core/wavelengths.h"
#include "integrators/direct_lighting.h"
#include "integrators/estimators.h"
#include "integrators/radiosity_solver.h"
#include "lights/light_sampler.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace candela {

namespace {

// The solution at the vertices, per side (0 front, 1 back): irradiance, reflected radiosity
// (reflectance x irradiance) and radiosity (emitted + reflected).
struct VertexSolution {
    std::vector<Spectrum> irradiance[2], reflected[2], radiosity[2];
};

VertexSolution vertex_solution(const RadiosityPatches& patches, const std::vector<Spectrum>& irradiance) {
    const auto& elements = patches.elements();
    std::vector<Spectrum> reflected(elements.size()), radiosity(elements.size());
    for (size_t i = 0; i < elements.size(); ++i) {
        reflected[i] = elements[i].reflectance * irradiance[i];
        radiosity[i] = elements[i].emitted + reflected[i];
    }
    VertexSolution v;
    for (int side = 0; side < 2; ++side) {
        v.irradiance[side] = patches.vertex_average(irradiance, side == 1);
        v.reflected[side] = patches.vertex_average(reflected, side == 1);
        v.radiosity[side] = patches.vertex_average(radiosity, side == 1);
    }
    return v;
}

}  // namespace

std::vector<RadiosityMesh> bake_radiosity(const Scene& scene, const RadiositySettings& settings, const RenderOptions& options,
                                          RadiosityStats* stats) {
    RadiosityPatches patches(scene, settings);
    RadiosityStats local;
    RadiosityStats& st = stats ? *stats : local;
    std::vector<Spectrum> irradiance = solve_radiosity(patches, scene, settings, options, "", SourceLocation{scene.source_file, 0}, st);
    VertexSolution v = vertex_solution(patches, irradiance);
    return patches.meshes(v.irradiance[0], v.irradiance[1], v.radiosity[0]);
}

std::vector<RadiosityMesh> bake_path_irradiance(const Scene& scene, const RadiositySettings& settings, int samples,
                                                const RenderOptions& options) {
    RadiosityPatches patches(scene, settings);
    const std::vector<Spectrum> none(patches.vertex_count(), Spectrum(0.0f));
    const std::vector<RadiosityMesh> geometry = patches.meshes(none, none, none);
    const auto& elements = patches.elements();
    std::vector<Vec3> points(elements.size()), normals(elements.size());
    for (size_t i = 0; i < elements.size(); ++i) {
        const RadiosityElement& e = elements[i];
        const TriangleSoup& soup = geometry[e.mesh].patches;
        const glm::uvec3& t = soup.triangles[e.triangle];
        float gap = tessellation_gap(soup.positions[t.x], soup.positions[t.y], soup.positions[t.z], soup.normals[t.x], soup.normals[t.y],
                                     soup.normals[t.z]);
        points[i] = e.centroid + e.normal * gap;
        normals[i] = e.normal;
    }
    EstimatorOptions eo;
    eo.samples = uint64_t(std::max(samples, 1));
    eo.seed = settings.seed;
    eo.threads = options.threads;
    std::vector<Spectrum> irradiance = estimate_irradiance_at(scene, points, normals, eo);
    VertexSolution v = vertex_solution(patches, irradiance);
    return patches.meshes(v.irradiance[0], v.irradiance[1], v.radiosity[0]);
}

class RadiosityIntegrator final : public SamplingIntegrator {
public:
    explicit RadiosityIntegrator(const Properties& props) {
        settings_.max_patch_area = props.get_float("max_patch_area", 0.0f);
        settings_.subdivisions = props.get_int("subdivisions", 0);
        if (props.has("max_patch_area") && props.has("subdivisions"))
            props.fail("subdivisions", "give max_patch_area or subdivisions, not both");
        if (props.has("max_patch_area") && !(settings_.max_patch_area > 0.0f))
            props.fail("max_patch_area", "max_patch_area must be positive");
        if (props.has("subdivisions") && settings_.subdivisions <= 0) props.fail("subdivisions", "subdivisions must be positive");
        settings_.tolerance = props.get_float("tolerance", 1e-3f);
        if (!(settings_.tolerance > 0.0f && settings_.tolerance < 1.0f)) props.fail("tolerance", "tolerance must lie between 0 and 1");
        settings_.max_iterations = props.get_int("max_iterations", 100000);
        if (settings_.max_iterations < 0) props.fail("max_iterations", "max_iterations must not be negative");
        settings_.visibility_rays = props.get_int("visibility_rays", 16);
        if (settings_.visibility_rays <= 0) props.fail("visibility_rays", "visibility_rays must be positive");
        settings_.seed = uint64_t(int64_t(props.get_int("seed", 0)));
        final_gather_ = props.get_bool("final_gather", true);
        location_ = props.location();
        std::string file = props.get_string("solution", "");
        if (!file.empty()) {
            std::filesystem::path p(file);
            if (p.is_relative() && !props.location_of("solution").file.empty())
                p = std::filesystem::path(props.location_of("solution").file).parent_path() / p;
            solution_file_ = p.string();
        }
    }

    // Its patches are one still tessellation.
    bool renders_motion() const override { return false; }
    RenderResult render(const Scene& scene, const RenderOptions& options) override {
        refuse_unrendered_media(scene);
        refuse_unrendered_motion(scene);
        auto start = std::chrono::steady_clock::now();
        patches_ = std::make_unique<RadiosityPatches>(scene, settings_);
        RadiosityStats stats;
        std::vector<Spectrum> irradiance = solve_radiosity(*patches_, scene, settings_, options, solution_file_, location_, stats);
        solution_ = vertex_solution(*patches_, irradiance);
        RenderResult result;
        if (stats.interrupted) {
            // Stopped during the solve: show what there is, quickly, as a partial image.
            RenderOptions quick = options;
            quick.interrupt = nullptr;
            quick.spp = 1;
            quick.progress = false;
            result = SamplingIntegrator::render(scene, quick);
            result.stats.partial = true;
        } else {
            result = SamplingIntegrator::render(scene, options);
        }
        result.stats.rays += stats.rays;
        result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (options.progress) {
            std::fprintf(stderr, "radiosity: %zu patches, %s %d shots, unshot %.3g%% of the emitted power%s\n", stats.patches,
                         stats.loaded ? "read from the solution file:" : "", stats.shots, 100.0 * stats.unshot_fraction,
                         stats.converged ? "" : " (not converged)");
        }
        stats_ = stats;
        return result;
    }

    const RadiosityStats& stats() const { return stats_; }

    void prepare(const Scene& scene) override { lights_ = create_light_sampler(DefaultLightSampler, scene); }

    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const override {
        SurfaceInteraction si;
        PatchHit hit;
        if (!patches_->intersect(ray, si, hit)) {
            record.valid = !scene.infinite_emitters().empty();
            return scene.eval_environment(ray.d, ray.wavelengths, ray.time);
        }
        record.valid = true;
        record.record_first_hit(si);
        if (!final_gather_) return hit.element < 0 ? Spectrum(0.0f) : InvPi * radiosity_at(solution_.radiosity, hit, si);
        return gather(scene, sampler, si);
    }

    std::string to_string() const override { return "radiosity"; }
    // The pixel loop alone could be split, but a render stopped during the solve shows a quick
    // one-sample preview of the unfinished solution, which is no part of the render.
    std::string parts_refusal() const override {
        return "a render stopped during its radiosity solve shows a one-sample preview of the unfinished solution, which no part may hold";
    }

private:
    // The solution at a hit, as radiance at the hit's wavelengths (RGB in the RGB variant).
    Spectrum radiosity_at(const std::vector<Spectrum> (&values)[2], const PatchHit& hit, const SurfaceInteraction& at) const {
        const Spectrum rgb = RadiosityPatches::interpolate(values[patches_->elements()[size_t(hit.element)].back ? 1 : 0], hit);
        return rgb_at_wavelengths(rgb, SpectrumRole::Emission, at.wavelengths);
    }

    // Final gather at a camera hit: emission, direct light by light sampling, and one bounce
    // whose ray reads the reflected radiosity where it lands. The emission found by that ray
    // counts only after a delta lobe (light sampling cannot reach it); otherwise the direct term
    // already holds it.
    Spectrum gather(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si) const {
        const BSDFContext ctx;
        const BSDF& bsdf = *si.shape->bsdf();
        Spectrum L(0.0f);
        if (const Emitter* emitter = si.shape->emitter()) L += emitter->eval(si);
        if (bsdf.has_smooth_lobe()) L += direct_light(sampler, si, bsdf);
        float u_lobe = draw_lobe_number(bsdf, sampler);
        BSDFSample bs = bsdf.sample(ctx, si, u_lobe, sampler.next_2d());
        if (!bs.valid() || is_black(bs.weight)) return L;
        if (bs.dispersed && si.wavelengths) si.wavelengths->terminate_secondary();
        bool delta = is_delta(bs.lobe);
        Ray ray = si.spawn_ray(si.to_world(bs.wo));
        SurfaceInteraction y;
        PatchHit hit;
        if (!patches_->intersect(ray, y, hit)) return delta ? L + bs.weight * scene.eval_environment(ray.d, ray.wavelengths, ray.time) : L;
        Spectrum incoming = hit.element < 0 ? Spectrum(0.0f) : InvPi * radiosity_at(solution_.reflected, hit, y);
        if (delta && y.shape->emitter()) incoming += y.shape->emitter()->eval(y);
        return L + bs.weight * incoming;
    }

    // One light sample, its shadow ray traced through the patches.
    Spectrum direct_light(Sampler& sampler, const SurfaceInteraction& si, const BSDF& bsdf) const {
        const LightSample light = draw_light_sample(*lights_, sampler, si);
        if (!light.valid()) return Spectrum(0.0f);
        Spectrum f = bsdf.eval(BSDFContext(), si, si.to_local(light.ds.d));
        if (is_black(f)) return Spectrum(0.0f);
        if (patches_->occluded_except(shadow_ray(si, light.ds), light.emitter->shape())) return Spectrum(0.0f);
        return f * light.weight / light.pick_prob;
    }

    RadiositySettings settings_;
    bool final_gather_ = true;
    std::string solution_file_;
    SourceLocation location_;  // of the integrator, for warnings
    std::unique_ptr<RadiosityPatches> patches_;
    VertexSolution solution_;
    std::unique_ptr<LightSampler> lights_;
    RadiosityStats stats_;
};

CANDELA_REGISTER_SPECTRAL(RadiosityIntegrator, ObjectKind::Integrator, "radiosity");

const RadiosityStats* radiosity_stats(const Integrator& integrator) {
    auto* radiosity = dynamic_cast<const RadiosityIntegrator*>(&integrator);
    return radiosity ? &radiosity->stats() : nullptr;
}

}  // namespace candela
