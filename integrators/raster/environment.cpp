#include "integrators/raster/environment.h"

#include "core/error.h"
#include "core/image.h"

namespace candela::raster {

namespace {
const char* FaceNames[6] = {"px", "nx", "py", "ny", "pz", "nz"};
}

void EnvironmentLookup::direction_to_face(const Vec3& d, int& face, float& s, float& t) {
    Vec3 a = glm::abs(d);
    float sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x > 0 ? 0 : 1;
        ma = a.x;
        sc = d.x > 0 ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y > 0 ? 2 : 3;
        ma = a.y;
        sc = d.x;
        tc = d.y > 0 ? d.z : -d.z;
    } else {
        face = d.z > 0 ? 4 : 5;
        ma = a.z;
        sc = d.z > 0 ? d.x : -d.x;
        tc = -d.y;
    }
    s = 0.5f * (sc / ma + 1.0f);
    t = 0.5f * (tc / ma + 1.0f);
}

Vec3 EnvironmentLookup::face_to_direction(int face, float s, float t) {
    float sc = 2.0f * s - 1.0f, tc = 2.0f * t - 1.0f;
    switch (face) {
        case 0: return glm::normalize(Vec3(1.0f, -tc, -sc));
        case 1: return glm::normalize(Vec3(-1.0f, -tc, sc));
        case 2: return glm::normalize(Vec3(sc, 1.0f, tc));
        case 3: return glm::normalize(Vec3(sc, -1.0f, -tc));
        case 4: return glm::normalize(Vec3(sc, -tc, 1.0f));
        default: return glm::normalize(Vec3(-sc, -tc, -1.0f));
    }
}

std::string EnvironmentLookup::face_file(const std::string& pattern, int face) {
    std::string path = pattern;
    size_t at = path.find("{face}");
    if (at == std::string::npos) throw InputError("cube_map \"" + pattern + "\" must contain {face}");
    return path.replace(at, 6, FaceNames[face]);
}

EnvironmentLookup::EnvironmentLookup(const Scene& scene, Mode mode, int resolution, const std::string& pattern)
    : scene_(scene), mode_(mode) {
    empty_ = scene.infinite_emitters().empty() && pattern.empty();
    if (mode != Mode::Cube || empty_) return;
    for (int f = 0; f < 6; ++f) {
        std::vector<Spectrum> texels;
        int w = resolution, h = resolution;
        if (!pattern.empty()) {
            Image img = read_image(face_file(pattern, f));
            w = img.width();
            h = img.height();
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) texels.push_back(img.linear_rgb_at(x, y));
        } else {
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    texels.push_back(scene.eval_environment(face_to_direction(f, (x + 0.5f) / float(w), (y + 0.5f) / float(h))));
        }
        faces_[size_t(f)] = MipMap(std::move(texels), w, h, WrapMode::Clamp);
    }
}

Spectrum EnvironmentLookup::lookup(const Vec3& d, float roughness) const {
    if (empty_) return Spectrum(0.0f);
    if (mode_ == Mode::LatLong) return scene_.eval_environment(d);
    int face;
    float s, t;
    direction_to_face(d, face, s, t);
    const MipMap& m = faces_[size_t(face)];
    float level = std::clamp(roughness, 0.0f, 1.0f) * float(m.levels() - 1);
    int l0 = int(level);
    float f = level - float(l0);
    Spectrum a = m.bilinear(l0, Vec2(s, t));
    if (f <= 0.0f || l0 + 1 >= m.levels()) return a;
    return a * (1.0f - f) + m.bilinear(l0 + 1, Vec2(s, t)) * f;
}

}  // namespace candela::raster
