// cube: the cube [-1, 1]^3 as 12 triangles with outward normals, placed by to_world.
//
// Parameters:
//   to_world       transform   object to world (default identity)
//   flip_normals   boolean     make the inside the front side (default false)
// Each face has its own four vertices with Mitsuba 3's uv layout.

#include "core/mesh.h"
#include "core/registry.h"

namespace candela {

class Cube final : public Mesh {
public:
    explicit Cube(const Properties& props) : Mesh(props) {
        // Per face: four corners counter-clockwise seen from outside; uv (0,1), (1,1), (1,0), (0,0).
        static const float faces[6][4][3] = {
            {{1, -1, -1}, {1, -1, 1}, {-1, -1, 1}, {-1, -1, -1}},  // -y
            {{1, 1, -1}, {-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}},      // +y
            {{1, -1, -1}, {1, 1, -1}, {1, 1, 1}, {1, -1, 1}},      // +x
            {{1, -1, 1}, {1, 1, 1}, {-1, 1, 1}, {-1, -1, 1}},      // +z
            {{-1, -1, 1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, -1}},  // -x
            {{1, 1, -1}, {1, -1, -1}, {-1, -1, -1}, {-1, 1, -1}},  // -z
        };
        static const float face_uv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
        for (unsigned f = 0; f < 6; ++f) {
            for (int k = 0; k < 4; ++k) {
                positions_.emplace_back(faces[f][k][0], faces[f][k][1], faces[f][k][2]);
                uvs_.emplace_back(face_uv[k][0], face_uv[k][1]);
            }
            unsigned b = 4 * f;
            triangles_.push_back({b, b + 1, b + 2});
            triangles_.push_back({b + 3, b, b + 2});
        }
        finalize(props, false);
    }
    std::string to_string() const override { return "cube"; }
};

CANDELA_REGISTER(Cube, ObjectKind::Shape, "cube");

}  // namespace candela
