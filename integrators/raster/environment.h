#pragma once
// Environment mapping for the local model: the radiance arriving from a direction, looked up
// either in the scene's environment directly (its lat-long map, through eval_environment) or in
// a cube map of six faces (OpenGL's face layout) built from that environment or loaded from
// images. Rough reflections read coarser MIP levels of the cube faces (level ~ alpha * levels).

#include "core/scene.h"
#include "textures/mipmap.h"

#include <array>
#include <string>

namespace candela::raster {

class EnvironmentLookup {
public:
    enum class Mode { LatLong, Cube };
    // `faces_pattern`, if not empty, names six images with "{face}" standing for px, nx, py, ny,
    // pz, nz; otherwise the faces are rendered from the scene's environment at `resolution`.
    EnvironmentLookup(const Scene& scene, Mode mode, int resolution, const std::string& faces_pattern);

    Spectrum lookup(const Vec3& direction, float roughness) const;
    bool empty() const { return empty_; }

    // Cube-face coordinates (OpenGL convention): face index 0..5 = +x, -x, +y, -y, +z, -z and
    // (s, t) in [0, 1]^2 with t = 0 at the top row.
    static void direction_to_face(const Vec3& d, int& face, float& s, float& t);
    static Vec3 face_to_direction(int face, float s, float t);
    // The image of one face: `pattern` with "{face}" replaced (InputError when it has none).
    static std::string face_file(const std::string& pattern, int face);

private:
    const Scene& scene_;
    Mode mode_;
    bool empty_ = true;
    std::array<MipMap, 6> faces_;
};

}  // namespace candela::raster
