// normalmap: replaces the shading normal of a nested BSDF by one read from a texture.
//
// Parameters (Mitsuba 3):
//   normalmap      texture   tangent-space normals encoded as rgb = (n + 1) / 2, in the shading
//                            frame (x along dp/du); use a bitmap with raw=true
//   (nested bsdf)  the BSDF to perturb
//   flip_invalid_normals, use_shadowing_function   see materials/perturbed_frame.h

#include "core/registry.h"
#include "core/texture.h"
#include "materials/perturbed_frame.h"

namespace candela {

class NormalMapBSDF final : public PerturbedFrameBSDF {
public:
    explicit NormalMapBSDF(const Properties& props) : PerturbedFrameBSDF(props) {
        auto map = std::dynamic_pointer_cast<Texture>(props.get_object("normalmap"));
        if (!map) props.fail("normalmap needs a texture named \"normalmap\"");
        map_ = map;
    }
    std::string to_string() const override { return "normalmap"; }

protected:
    // (2 rgb - 1): tangent-space normals, in the shading frame (x along dp/du).
    Vec3 perturbation(const SurfaceInteraction& si) const override { return 2.0f * map_->eval_rgb(si) - Vec3(1.0f); }

private:
    Ref<Texture> map_;
};

CANDELA_REGISTER_SPECTRAL(NormalMapBSDF, ObjectKind::BSDF, "normalmap");

}  // namespace candela
