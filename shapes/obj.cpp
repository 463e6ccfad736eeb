// obj: a Wavefront OBJ triangle mesh, read by Candela's own parallel OBJ parser.
//
// Parameters:
//   filename          string      the .obj file (relative to the scene file)
//   to_world          transform   object to world (default identity)
//   face_normals      boolean     ignore the file's normals and shade flat (default false)
//   flip_normals      boolean     swap front and back (default false)
//   flip_tex_coords   boolean     v -> 1 - v, the usual OBJ convention (default true)
// Read: v (x y z; a w or vertex colours after them are ignored), vt (u v), vn and f lines, with
// corners v, v/vt, v//vn or v/vt/vn and indices from 1 or negative (relative); o, g, s, usemtl,
// mtllib, l, p and comments (#) are skipped; lines may end in LF, CR LF or CR (a trailing backslash
// does not continue a line). Polygons with more than three corners are triangulated by ear
// clipping, so concave faces come out right. Corners are merged only when position, uv and normal
// indices all agree; the file's normals are used only when every corner has one, and without
// them angle-weighted smooth normals are computed (not across uv seams). A malformed number or a
// face corner that names a missing element is an error giving the file's line. The file is
// memory-mapped and parsed in parallel, chunks of it at a time.

#include "core/mapped_file.h"
#include "core/mesh.h"
#include "core/registry.h"
#include "shapes/obj_reader.h"

#include <memory>

namespace candela {

class ObjMesh final : public Mesh {
public:
    explicit ObjMesh(const Properties& props) : Mesh(props) {
        std::string path = props.get_file_path("filename");
        bool face_normals = props.get_bool("face_normals", false);
        ObjReadOptions options;
        options.flip_tex_coords = props.get_bool("flip_tex_coords", true);
        options.ignore_normals = face_normals;
        const SourceLocation where = props.location_of("filename");
        options.before_allocating = [&](uint64_t vertices, uint64_t triangles, uint64_t temporary) {
            check_mesh_memory(vertices, triangles, temporary, where);
        };
        std::unique_ptr<MappedFile> file;
        try {
            file = std::make_unique<MappedFile>(path);
        } catch (const std::runtime_error& e) {
            props.fail("filename", "OBJ file \"" + path + "\": " + e.what());
        }
        try {
            read_obj(reinterpret_cast<const char*>(file->data()), file->size(), options, positions_, uvs_, normals_, triangles_);
        } catch (const ObjError& e) {
            std::string at = e.line ? ", line " + std::to_string(e.line) : std::string();
            props.fail("filename", "OBJ file \"" + path + "\"" + at + ": " + e.what());
        }
        if (triangles_.empty()) props.fail("filename", "OBJ file \"" + path + "\" has no faces");
        finalize(props, !face_normals);
    }
    std::string to_string() const override { return "obj"; }
};

CANDELA_REGISTER(ObjMesh, ObjectKind::Shape, "obj");

}  // namespace candela
