// rectangle: the square [-1, 1]^2 in the z = 0 plane with normal +z, placed by to_world.
//
// Parameters:
//   to_world       transform   object to world (default identity)
//   flip_normals   boolean     make -z the front side (default false)
// uv = ((x + 1) / 2, (y + 1) / 2) in object space, as in Mitsuba 3.

#include "core/mesh.h"
#include "core/registry.h"

namespace candela {

class Rectangle final : public Mesh {
public:
    explicit Rectangle(const Properties& props) : Mesh(props) {
        positions_ = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
        uvs_ = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        triangles_ = {{0, 1, 2}, {0, 2, 3}};
        finalize(props, false);
    }
    std::string to_string() const override { return "rectangle"; }
};

CANDELA_REGISTER(Rectangle, ObjectKind::Shape, "rectangle");

}  // namespace candela
