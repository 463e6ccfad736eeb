#include "integrators/light_paths.h"

#include "core/wavelengths.h"

#include "core/random_2d.h"
#include "core/sampler.h"

namespace candela {

SampleSettings sample_settings(const Scene& scene, const RenderOptions& options) {
    // The count and seed of the sampler the pixel loop would use (rounded as it rounds them).
    const Ref<Sampler> sampler = configured_sampler(scene, options);
    SampleSettings s;
    s.spp = sampler->sample_count();
    s.seed = sampler->seed();
    return s;
}

PCG32 light_path_rng(uint64_t seed, uint64_t stream, uint64_t index) {
    return PCG32(hash_combine(hash_combine(seed, stream), index), hash_combine(~seed, hash_combine(stream, index)));
}

void scatter_stokes_forward(const SurfaceInteraction& si, const BSDF& bsdf, const Vec3& wo_local, uint32_t lobe, StokesSpectrum& s) {
    // eval_mueller's light arrives along -wo and leaves along wi: here it arrives along -si.wi.
    // Its directions are always the light's, so the context is the radiance one.
    SurfaceInteraction leaving = si;
    leaving.wi = wo_local;
    scatter_stokes(bsdf, BSDFContext(), leaving, si.wi, lobe, s);
}

float shading_normal_correction(const SurfaceInteraction& si, const Vec3& wo_local) {
    float wi_geo = glm::dot(si.n, si.wi_world()), wo_geo = glm::dot(si.n, si.to_world(wo_local));
    float wi_shading = Frame::cos_theta(si.wi), wo_shading = Frame::cos_theta(wo_local);
    if (!(wi_geo * wi_shading > 0.0f) || !(wo_geo * wo_shading > 0.0f)) return 0.0f;
    return std::abs((wi_shading * wo_geo) / (wo_shading * wi_geo));
}

LightPathTracer::LightPathTracer(const Scene& scene, int max_hits, int rr_depth)
    : scene_(scene),
      lights_(create_light_sampler("power", scene)),
      max_hits_(max_hits < 0 ? UINT32_MAX : uint32_t(max_hits)),
      rr_depth_(uint32_t(std::max(rr_depth, 1))) {}

float LightPathTracer::sample_time(PCG32& rng) const {
    const Sensor& sensor = scene_.sensor();
    return sensor.shutter_open_time() > 0.0f ? sensor.sample_time(rng.next_float()) : sensor.shutter_open();
}

bool LightPathTracer::start(PCG32& rng, float time, LightPathStart& s) const {
    float u_pick = rng.next_float();
    const Vec2 u_position = next_vec2(rng), u_direction = next_vec2(rng);
    s.emitter = lights_->sample(SurfaceInteraction(), u_pick, s.pick_prob);
    if (!s.emitter || !(s.pick_prob > 0.0f)) return false;
    s.ray = s.emitter->sample_ray(u_position, u_direction, s.wavelengths, time);
    s.ray.ray.time = time;
    if (!s.ray.valid() || is_black(s.ray.weight) || !all_finite(s.ray.weight)) return false;
    s.beta = s.ray.weight / s.pick_prob;
    return true;
}

bool LightPathTracer::scatter(PCG32& rng, const SurfaceInteraction& si, const BSDF& bsdf, Spectrum& beta, Vec3& wo_world,
                              uint32_t& lobe) const {
    BSDFContext ctx;
    ctx.mode = TransportMode::Importance;
    float u_lobe = rng.next_float();
    Vec2 u_dir = next_vec2(rng);
    BSDFSample bs = bsdf.sample(ctx, si, u_lobe, u_dir);
    if (!bs.valid() || is_black(bs.weight)) return false;
    if (bs.dispersed && si.wavelengths) si.wavelengths->terminate_secondary();
    float correction = shading_normal_correction(si, bs.wo);
    if (!(correction > 0.0f)) return false;
    beta *= bs.weight * correction;
    wo_world = si.to_world(bs.wo);
    lobe = bs.lobe;
    return max_component(beta) > 0.0f;
}

}  // namespace candela
