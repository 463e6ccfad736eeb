// obj: a Wavefront OBJ triangle mesh, read with tinyobjloader.
//
// Parameters:
//   filename          string      the .obj file (relative to the scene file)
//   to_world          transform   object to world (default identity)
//   face_normals      boolean     ignore the file's normals and shade flat (default false)
//   flip_normals      boolean     swap front and back (default false)
//   flip_tex_coords   boolean     v -> 1 - v, the usual OBJ convention (default true)
// Polygons with more than three corners are triangulated by ear clipping, so concave faces come
// out right. Corners are merged only when position, uv and normal indices all agree; without
// normals in the file, angle-weighted smooth normals are computed (not across uv seams).

#include "core/mesh.h"
#include "core/registry.h"
#include "geometry2d/polygon.h"

#include <tiny_obj_loader.h>

#include <map>
#include <tuple>

namespace candela {

class ObjMesh final : public Mesh {
public:
    explicit ObjMesh(const Properties& props) : Mesh(props) {
        std::string path = props.get_file_path("filename");
        bool face_normals = props.get_bool("face_normals", false);
        bool flip_tex = props.get_bool("flip_tex_coords", true);

        tinyobj::ObjReaderConfig config;
        config.triangulate = false;  // we triangulate ourselves (tinyobjloader fans concave faces)
        config.vertex_color = false;
        tinyobj::ObjReader reader;
        if (!reader.ParseFromFile(path, config)) props.fail("filename", "cannot read OBJ file \"" + path + "\": " + reader.Error());
        const tinyobj::attrib_t& attrib = reader.GetAttrib();
        bool file_has_normals = !attrib.normals.empty() && !face_normals;

        std::map<std::tuple<int, int, int>, unsigned> vertex_of;  // (v, vt, vn) -> mesh vertex
        auto vertex = [&](const tinyobj::index_t& idx) -> unsigned {
            int vn = file_has_normals ? idx.normal_index : -1;
            auto key = std::make_tuple(idx.vertex_index, idx.texcoord_index, vn);
            auto it = vertex_of.find(key);
            if (it != vertex_of.end()) return it->second;
            // Indices come from the file: widen them before scaling (3 * index overflows an int).
            const size_t v = size_t(idx.vertex_index), vt = size_t(idx.texcoord_index), n = size_t(vn);
            if (idx.vertex_index < 0 || 3 * v + 2 >= attrib.vertices.size())
                props.fail("filename", "OBJ file \"" + path + "\" refers to a vertex that does not exist");
            unsigned id = unsigned(positions_.size());
            positions_.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]);
            if (idx.texcoord_index >= 0 && 2 * vt + 1 < attrib.texcoords.size()) {
                float u = attrib.texcoords[2 * vt], tv = attrib.texcoords[2 * vt + 1];
                uvs_.emplace_back(u, flip_tex ? 1.0f - tv : tv);
                has_uv_ = true;
            } else {
                uvs_.emplace_back(0.0f);
            }
            if (vn >= 0 && 3 * n + 2 < attrib.normals.size()) {
                normals_.emplace_back(attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2]);
                has_normal_ = true;
            } else {
                normals_.emplace_back(0.0f);
                missing_normal_ = true;
            }
            vertex_of.emplace(key, id);
            return id;
        };

        for (const tinyobj::shape_t& shape : reader.GetShapes()) {
            size_t offset = 0;
            for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
                size_t count = shape.mesh.num_face_vertices[f];
                std::vector<unsigned> corner(count);
                for (size_t k = 0; k < count; ++k) corner[k] = vertex(shape.mesh.indices[offset + k]);
                offset += count;
                if (count < 3) continue;
                if (count == 3) {
                    triangles_.push_back({corner[0], corner[1], corner[2]});
                    continue;
                }
                std::vector<Vec3> pts(count);
                for (size_t k = 0; k < count; ++k) pts[k] = positions_[corner[k]];
                for (auto& t : triangulate_polygon_3d(pts)) triangles_.push_back({corner[t[0]], corner[t[1]], corner[t[2]]});
            }
        }
        if (triangles_.empty()) props.fail("filename", "OBJ file \"" + path + "\" has no faces");
        if (!has_uv_) uvs_.clear();
        // Normals only when every corner has one (a partial set would leave holes).
        if (!has_normal_ || missing_normal_) normals_.clear();
        finalize(props, !face_normals);
    }
    std::string to_string() const override { return "obj"; }

private:
    bool has_uv_ = false, has_normal_ = false, missing_normal_ = false;
};

CANDELA_REGISTER(ObjMesh, ObjectKind::Shape, "obj");

}  // namespace candela
