// mesh_attribute: a mesh's per-vertex or per-face data as a texture (vertex colours of a PLY
// file, ...).
//
// Parameters:
//   name    string   the attribute: "vertex_<name>" (interpolated across each triangle) or
//                    "face_<name>" (constant over each face), as the mesh loader named it
//   scale   float    factor applied to the value (default 1)
//
// One-channel attributes read as grey; scalar lookups (roughness, heights) take the luminance.
// The value exists only at a surface point of a mesh that has the attribute: a shape without it
// stops the render with an error at this texture's line, as Mitsuba does. Lookups by uv alone
// cannot be answered (the rasterizer, sampling an area emitter, averages for light power); they
// stop with the same kind of error instead of guessing.

#include "core/properties.h"
#include "core/registry.h"
#include "core/shape.h"
#include "core/texture.h"

namespace candela {

class MeshAttributeTexture final : public Texture {
public:
    explicit MeshAttributeTexture(const Properties& props) : where_(props.location()) {
        name_ = props.get_string("name");
        if (name_.rfind("vertex_", 0) != 0 && name_.rfind("face_", 0) != 0)
            props.fail("name", "a mesh attribute's name starts with \"vertex_\" or \"face_\", not \"" + name_ + "\"");
        scale_ = props.get_float("scale", 1.0f);
    }

    Spectrum eval_rgb(const SurfaceInteraction& si) const override {
        if (!si.shape) uv_only("a value away from any shape");
        Spectrum value;
        if (!si.shape->eval_attribute(name_, si, value))
            throw SceneError(where_,
                             "mesh_attribute: the " + si.shape->to_string() + " it is evaluated on has no attribute \"" + name_ + "\"");
        return value * scale_;
    }
    float eval_1(const SurfaceInteraction& si) const override { return luminance(eval_rgb(si)); }

    Spectrum eval(const Vec2&) const override { uv_only("a lookup by uv alone"); }
    Spectrum mean() const override { uv_only("its average"); }
    float max_value() const override { uv_only("its largest value"); }
    std::string to_string() const override { return "mesh_attribute"; }

private:
    [[noreturn]] void uv_only(const char* what) const {
        throw SceneError(where_, "mesh_attribute \"" + name_ + "\" is known only at the surface points of its mesh, but " + what +
                                     " was asked for (by the rasterizer, an emitter or a BSDF's energy check); this use is not supported");
    }

    std::string name_;
    float scale_ = 1.0f;
    SourceLocation where_;
};

CANDELA_REGISTER_SPECTRAL(MeshAttributeTexture, ObjectKind::Texture, "mesh_attribute");

}  // namespace candela
