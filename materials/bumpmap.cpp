// bumpmap: perturbs the shading normal of a nested BSDF by a height field (Blinn 1978).
//
// Parameters (Mitsuba 3):
//   (nested texture)   the height h(u, v); for rgb textures the luminance is used
//   scale              float   height scale (default 1)
//   (nested bsdf)      the BSDF to perturb
//   flip_invalid_normals, use_shadowing_function   see materials/perturbed_frame.h
//
// With (g_u, g_v) = scale * dh/d(u, v) and n the shading normal, the tangents become
// dp/du' = dp/du + n (g_u - n . dp/du) and dp/dv' = dp/dv + n (g_v - n . dp/dv), and the new
// normal is their cross product (flipped to the geometric normal's side), handed to
// materials/perturbed_frame.h in the shading frame's coordinates.

#include "core/local_model.h"
#include "core/registry.h"
#include "core/texture.h"
#include "materials/perturbed_frame.h"

namespace candela {

class BumpMapBSDF final : public PerturbedFrameBSDF {
public:
    explicit BumpMapBSDF(const Properties& props) : PerturbedFrameBSDF(props) {
        auto textures = props.get_objects(ObjectKind::Texture);
        if (textures.size() != 1) props.fail("bumpmap needs exactly one nested height texture");
        height_ = std::static_pointer_cast<Texture>(textures[0]);
        scale_ = props.get_float("scale", 1.0f);
    }
    // Local model: the nested BSDF's, with this height field for displacement mapping.
    LocalShading local_shading() const override {
        LocalShading s = PerturbedFrameBSDF::local_shading();
        s.height = height_;
        s.height_scale = scale_;
        return s;
    }
    std::string to_string() const override { return "bumpmap"; }

protected:
    Vec3 perturbation(const SurfaceInteraction& si) const override {
        Vec2 g = scale_ * height_->eval_1_gradient(si);
        const Vec3& n = si.shading.n;
        Vec3 dpdu = si.dpdu + n * (g.x - glm::dot(n, si.dpdu));
        Vec3 dpdv = si.dpdv + n * (g.y - glm::dot(n, si.dpdv));
        Vec3 np = glm::cross(dpdu, dpdv);
        if (glm::dot(np, si.n) < 0.0f) np = -np;
        return si.shading.to_local(np);
    }

private:
    Ref<Texture> height_;
    float scale_ = 1.0f;
};

CANDELA_REGISTER_SPECTRAL(BumpMapBSDF, ObjectKind::BSDF, "bumpmap");

}  // namespace candela
