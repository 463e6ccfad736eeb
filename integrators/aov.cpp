// aov: arbitrary output variables, what the camera sees first at each sample, beside the images
// of nested integrators (Mitsuba 3's `aov`).
//
// Parameters (Mitsuba 3):
//   aovs             string    required: "name:type" pairs separated by commas or spaces, such
//                              as "dd.y:depth, nn:sh_normal"; each adds channels name.X, ... :
//     albedo         .R .G .B  the BSDF's albedo (BSDF::albedo, Mitsuba's diffuse reflectance;
//                              an approximation for some BSDFs)
//     depth          .T        distance along the camera ray from the near plane, where
//                              Mitsuba's camera rays start (core/ray.h, camera_depth)
//     position       .X .Y .Z  world-space hit point
//     uv             .U .V     texture coordinates
//     geo_normal     .X .Y .Z  geometric normal (the shape's front side)
//     sh_normal      .X .Y .Z  shading normal (interpolated or analytic; before bump maps)
//     dp_du, dp_dv   .X .Y .Z  position partials with respect to u and v
//     duv_dx, duv_dy .U .V     uv partials per step of the ray differentials: one pixel along
//                              x or y times 1 / sqrt(spp), as Mitsuba scales them (the offset rays
//                              meet the hit's tangent plane; Pharr et al., pbrt, 10.1.1)
//     prim_index     .I        primitive index (the triangle of a mesh)
//     shape_index    .I        1 + the shape's index in the scene (0: nothing hit)
//   (nested integrators)       sampling integrators rendered along, in document order, each
//                              named by its name attribute: channels name.R, .G, .B, .A (A: its
//                              valid flag), then each one's own channels as name.<channel>
//   hide_emitters    boolean   read and ignored, as Mitsuba reads it for every sampling
//                              integrator (the nested ones have their own)
// Without AOVs and nested integrators the image is black (a warning, as in Mitsuba).
// The film's own channels carry the first nested integrator's image (black without one); a
// sample is valid (the film's alpha) as that integrator says. AOVs of a ray that hits nothing
// are 0. Every value is filtered by the film's reconstruction filter like the radiance, so
// integer AOVs are fractional where a pixel sees more than one primitive (as in Mitsuba).

#include "core/bsdf.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/text.h"
#include "core/warning.h"
#include "core/wavelengths.h"
#include "integrators/nested.h"

#include <unordered_map>

namespace candela {

namespace {

enum class AovType { Albedo, Depth, Position, UV, GeoNormal, ShNormal, DpDu, DpDv, DuvDx, DuvDy, PrimIndex, ShapeIndex };

struct AovTypeInfo {
    const char* name;
    AovType type;
    const char* suffixes;  // one letter per channel
};

constexpr AovTypeInfo AovTypes[] = {{"albedo", AovType::Albedo, "RGB"},        {"depth", AovType::Depth, "T"},
                                    {"position", AovType::Position, "XYZ"},    {"uv", AovType::UV, "UV"},
                                    {"geo_normal", AovType::GeoNormal, "XYZ"}, {"sh_normal", AovType::ShNormal, "XYZ"},
                                    {"dp_du", AovType::DpDu, "XYZ"},           {"dp_dv", AovType::DpDv, "XYZ"},
                                    {"duv_dx", AovType::DuvDx, "UV"},          {"duv_dy", AovType::DuvDy, "UV"},
                                    {"prim_index", AovType::PrimIndex, "I"},   {"shape_index", AovType::ShapeIndex, "I"}};

std::string aov_type_list() {
    std::string list;
    for (const auto& t : AovTypes) list += (list.empty() ? "" : ", ") + std::string(t.name);
    return list;
}

// The uv partials of a hit for offset rays (o + t d) one differential step away in x and y:
// where they meet the tangent plane at si, expressed in dp_du, dp_dv by least squares.
void uv_partials(const SurfaceInteraction& si, const Ray& rx, const Ray& ry, Vec2& duv_dx, Vec2& duv_dy) {
    float a00 = glm::dot(si.dpdu, si.dpdu), a01 = glm::dot(si.dpdu, si.dpdv), a11 = glm::dot(si.dpdv, si.dpdv);
    float inv_det = 1.0f / (a00 * a11 - a01 * a01);
    if (!std::isfinite(inv_det)) inv_det = 0.0f;
    auto partial = [&](const Ray& r) {
        float t = glm::dot(si.n, si.p - r.o) / glm::dot(si.n, r.d);
        Vec3 dp = r.o + t * r.d - si.p;
        float b0 = glm::dot(si.dpdu, dp), b1 = glm::dot(si.dpdv, dp);
        Vec2 duv((a11 * b0 - a01 * b1) * inv_det, (a00 * b1 - a01 * b0) * inv_det);
        return all_finite(Vec3(duv, 0.0f)) ? duv : Vec2(0.0f);
    };
    duv_dx = partial(rx);
    duv_dy = partial(ry);
}

}  // namespace

class AovIntegrator final : public SamplingIntegrator {
public:
    explicit AovIntegrator(const Properties& props) : nested_(read_nested_integrators(props)) {
        props.get_bool("hide_emitters", false);
        for (const NestedIntegrator& n : nested_)
            for (const char* c : {".R", ".G", ".B", ".A"}) names_.push_back(n.name + c);
        for (const NestedIntegrator& n : nested_)
            for (const std::string& c : n.channels) names_.push_back(n.name + "." + c);
        for (const std::string& item : split_list(props.get_string("aovs"))) {
            size_t colon = item.find(':');
            if (colon == std::string::npos || colon == 0 || colon + 1 == item.size() || item.find(':', colon + 1) != std::string::npos)
                props.fail("aovs", "\"" + item + "\" is not a name:type pair");
            std::string name = item.substr(0, colon), type = item.substr(colon + 1);
            const AovTypeInfo* info = nullptr;
            for (const auto& t : AovTypes)
                if (type == t.name) info = &t;
            if (!info) props.fail("aovs", "unknown AOV type \"" + type + "\" (" + aov_type_list() + ")");
            types_.push_back(info->type);
            for (const char* c = info->suffixes; *c; ++c) names_.push_back(name + "." + *c);
        }
        if (names_.size() > size_t(MaxSampleChannels))
            props.fail("aovs", "these AOVs need " + std::to_string(names_.size()) + " channels, more than the " +
                                   std::to_string(MaxSampleChannels) + " Candela supports");
        if (names_.empty()) warn(props.location(), "aov has no AOV and no nested integrator: the image will be black");
    }

    void prepare(const Scene& scene) override {
        for (const NestedIntegrator& n : nested_) n.integrator->prepare(scene);
        shape_index_.clear();
        for (size_t i = 0; i < scene.shapes().size(); ++i) shape_index_[scene.shapes()[i].get()] = uint32_t(i + 1);
    }

    std::vector<std::string> channel_names() const override { return names_; }

    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const override {
        Spectrum result(0.0f);
        float* rgba = record.channels;
        float* out = record.channels + 4 * nested_.size();
        for (size_t i = 0; i < nested_.size(); ++i) {
            SampleRecord inner;
            Spectrum L = sample_nested(nested_[i], scene, sampler, ray, record, inner);
            // Channels are colours: in the spectral variant the nested values through CIE 1931
            // (the film's own channels, `result`, are converted by the pixel loop).
            const Spectrum colour = ray.wavelengths ? spectral_to_linear_srgb(L, *ray.wavelengths) : L;
            for (int k = 0; k < 3; ++k) *rgba++ = colour[k];
            *rgba++ = inner.valid ? 1.0f : 0.0f;
            for (size_t c = 0; c < nested_[i].channels.size(); ++c) *out++ = inner.channels[c];
            if (i == 0) {
                result = L;
                record.valid = inner.valid;
            }
        }
        SurfaceInteraction si;
        bool hit = scene.intersect(ray, si);
        if (hit) record.record_first_hit(si);
        for (AovType type : types_) out = write_aov(type, hit, si, scene, ray, record, out);
        return result;
    }

    std::string to_string() const override { return "aov"; }

private:
    // Writes one AOV of the first hit (zeros when nothing is hit); returns the next free slot.
    float* write_aov(AovType type, bool hit, const SurfaceInteraction& si, const Scene& scene, const Ray& ray, const SampleRecord& record,
                     float* out) const {
        auto put3 = [&](const Vec3& v) {
            for (int k = 0; k < 3; ++k) *out++ = hit ? v[k] : 0.0f;
        };
        auto put2 = [&](const Vec2& v) {
            for (int k = 0; k < 2; ++k) *out++ = hit ? v[k] : 0.0f;
        };
        switch (type) {
            case AovType::Albedo: {
                // A colour in every variant: the BSDF's albedo in RGB.
                SurfaceInteraction rgb = si;
                rgb.wavelengths = nullptr;
                put3(hit ? si.shape->bsdf()->albedo(rgb) : Spectrum(0.0f));
                break;
            }
            case AovType::Depth: *out++ = hit ? camera_depth(ray, si.t) : 0.0f; break;
            case AovType::Position: put3(si.p); break;
            case AovType::UV: put2(si.uv); break;
            case AovType::GeoNormal: put3(si.n); break;
            case AovType::ShNormal: put3(si.shading.n); break;
            case AovType::DpDu: put3(si.dpdu); break;
            case AovType::DpDv: put3(si.dpdv); break;
            case AovType::DuvDx:
            case AovType::DuvDy: {
                Vec2 dx(0.0f), dy(0.0f);
                if (hit)
                    uv_partials(si, differential_ray(scene, ray, record, Vec2(1, 0)), differential_ray(scene, ray, record, Vec2(0, 1)), dx,
                                dy);
                put2(type == AovType::DuvDx ? dx : dy);
                break;
            }
            case AovType::PrimIndex: *out++ = hit ? float(si.prim_index) : 0.0f; break;
            case AovType::ShapeIndex: {
                auto it = hit ? shape_index_.find(si.shape) : shape_index_.end();
                *out++ = it == shape_index_.end() ? 0.0f : float(it->second);
                break;
            }
        }
        return out;
    }

    // Mitsuba's ray differential: the camera ray one pixel away along `step` (same aperture
    // sample), scaled toward `ray` by the record's differential scale.
    static Ray differential_ray(const Scene& scene, const Ray& ray, const SampleRecord& record, const Vec2& step) {
        Ray offset = scene.sensor().sample_ray(record.film_pos + step, record.aperture, ray.time);
        float s = record.differential_scale;
        Ray differential(ray.o + (offset.o - ray.o) * s, ray.d + (offset.d - ray.d) * s);
        differential.time = ray.time;
        return differential;
    }

    std::vector<NestedIntegrator> nested_;
    std::vector<AovType> types_;
    std::vector<std::string> names_;
    std::unordered_map<const Shape*, uint32_t> shape_index_;
};

CANDELA_REGISTER_SPECTRAL(AovIntegrator, ObjectKind::Integrator, "aov");

}  // namespace candela
