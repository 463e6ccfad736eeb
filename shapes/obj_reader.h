#pragma once
// Candela's Wavefront OBJ reader, the parser of the obj shape plugin (shapes/obj.cpp).
//
// It reads `v`, `vt` and `vn` lines and the `f` lines whose corners are `v`, `v/vt`, `v//vn` or
// `v/vt/vn`, with indices from 1 or negative (relative to the elements defined so far); every
// other line (o, g, s, usemtl, mtllib, l, p, comments, ...) is skipped. Lines end with \n, \r\n
// or \r; a '#' anywhere starts a comment; a trailing backslash does not continue a line. A `v`
// line may carry more numbers than x y z (w, vertex colours): they are checked and ignored, as
// are a `vt` line's w and a `vn` line's extras; a `vt` line's v defaults to 0.
//
// The text is cut into chunks at line starts and parsed in parallel (core/parallel.h) in two
// passes: the first counts each chunk's lines of each kind, the second parses every chunk
// straight into its slice of the final arrays, sized from the counts. The result depends
// neither on the chunks nor on the threads, and an error is always the file's first.
//
// Corners that agree in position, uv and normal index are one vertex, numbered in the order the
// faces first use them (faces with fewer than three corners are dropped first). When no face
// names a uv or a normal, a corner's vertex follows from its position index alone (no hash
// table); otherwise an open-addressing table keyed by the three indices merges them. Polygons are
// triangulated by ear clipping (geometry2d/polygon.h). uvs are filled when some vertex has one
// (0, 0 for the others), normals only when every vertex has one.

#include "core/math.h"
#include "core/mesh_array.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace candela {

struct ObjReadOptions {
    bool flip_tex_coords = true;  // v -> 1 - v
    bool ignore_normals = false;  // the file's normals neither split corners nor reach the mesh
    // The bytes of text per chunk (cut at the next line start); 0 chooses from the size.
    size_t chunk_bytes = 0;
    // Called once the lines are counted, before the arrays are allocated: the vertices (an
    // estimate when corners are merged), the triangles, and the bytes of the reader's own
    // temporaries. The plugin checks the memory budget here (core/memory_budget.h).
    std::function<void(uint64_t vertices, uint64_t triangles, uint64_t temporary_bytes)> before_allocating;
};

// A malformed file: what is wrong, and on which line (from 1; 0 when no single line is).
class ObjError : public std::runtime_error {
public:
    ObjError(uint64_t line, const std::string& message) : std::runtime_error(message), line(line) {}
    uint64_t line;
};

// Parses `size` bytes of OBJ text into a mesh's arrays (replacing what they held). Each array is
// allocated once at its final size; `positions` with room for one more element (Embree reads
// vertices with 16-byte loads, core/mesh.cpp). Throws ObjError, leaving the arrays empty.
void read_obj(const char* text, size_t size, const ObjReadOptions& options, MeshArray<Vec3>& positions, MeshArray<Vec2>& uvs,
              MeshArray<Vec3>& normals, MeshArray<glm::uvec3>& triangles);

}  // namespace candela
