#include "integrators/radiosity_solver.h"

#include "core/bsdf.h"
#include "core/emitter.h"
#include "core/error.h"
#include "core/local_model.h"
#include "core/mesh.h"
#include "core/scene.h"

#include <array>
#include <map>

namespace candela {

namespace {

constexpr size_t MaxPatches = 2000000;

// Patches per triangle side for a triangle of `area`.
int subdivision_for(float area, const RadiositySettings& settings, float default_patch_area) {
    if (settings.subdivisions > 0) return settings.subdivisions;
    float max_area = settings.max_patch_area > 0.0f ? settings.max_patch_area : default_patch_area;
    return std::max(1, int(std::ceil(std::sqrt(area / max_area))));
}

bool is_invisible(const Shape& shape) { return shape.bsdf()->flags() == Null; }

float triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5f * glm::length(glm::cross(b - a, c - a)); }

// Splits every triangle of `in` into n x n triangles on the barycentric grid (i, j) with weights
// (n - i - j, i, j) / n. A point on an edge is computed from that edge's two end points alone
// (the third weight is zero), so neighbouring triangles with the same n produce bit-identical
// points there, which the vertex welding relies on.
TriangleSoup subdivide(const TriangleSoup& in, const RadiositySettings& settings, float default_patch_area) {
    TriangleSoup out;
    out.closed = in.closed;
    for (const glm::uvec3& t : in.triangles) {
        const Vec3 p[3] = {in.positions[t.x], in.positions[t.y], in.positions[t.z]};
        const Vec3 nrm[3] = {in.normals[t.x], in.normals[t.y], in.normals[t.z]};
        const Vec2 uv[3] = {in.uvs[t.x], in.uvs[t.y], in.uvs[t.z]};
        int n = subdivision_for(triangle_area(p[0], p[1], p[2]), settings, default_patch_area);
        float fn = float(n);
        unsigned base = unsigned(out.positions.size());
        std::vector<unsigned> row_start(size_t(n) + 2);
        for (int i = 0, count = 0; i <= n + 1; ++i) {
            row_start[size_t(i)] = unsigned(count);
            count += n + 1 - i;
        }
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                float w0 = float(n - i - j), w1 = float(i), w2 = float(j);
                out.positions.push_back((p[0] * w0 + p[1] * w1 + p[2] * w2) / fn);
                Vec3 ni = nrm[0] * w0 + nrm[1] * w1 + nrm[2] * w2;
                out.normals.push_back(squared_length(ni) > 0.0f ? glm::normalize(ni) : nrm[0]);
                out.uvs.push_back((uv[0] * w0 + uv[1] * w1 + uv[2] * w2) / fn);
            }
        auto at = [&](int i, int j) { return base + row_start[size_t(i)] + unsigned(j); };
        auto add = [&](unsigned a, unsigned b, unsigned c) {
            // Mesh::finalize drops zero-area triangles; drop them first so indices stay aligned.
            float area = triangle_area(out.positions[a], out.positions[b], out.positions[c]);
            if (area > 0.0f && std::isfinite(area)) out.triangles.emplace_back(a, b, c);
        };
        for (int i = 0; i < n; ++i)
            for (int j = 0; i + j < n; ++j) {
                add(at(i, j), at(i + 1, j), at(i, j + 1));
                if (i + j + 1 < n) add(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            }
    }
    return out;
}

void fnv1a(uint64_t& h, const void* data, size_t size) {
    const unsigned char* bytes = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
        h ^= bytes[i];
        h *= 0x100000001b3ULL;
    }
}

}  // namespace

// A scene shape's patches as a triangle mesh in world space (its front side is the shape's).
class RadiosityPatches::PatchMesh final : public Mesh {
public:
    PatchMesh(const Properties& props, const Shape* source, uint32_t index, TriangleSoup soup)
        : Mesh(props), source_(source), index_(index) {
        positions_ = std::move(soup.positions);
        normals_ = std::move(soup.normals);
        uvs_ = std::move(soup.uvs);
        triangles_ = std::move(soup.triangles);
        closed_ = soup.closed;
        finalize(props, false);
    }
    const Shape* source() const { return source_; }
    uint32_t index() const { return index_; }
    bool closed() const { return closed_; }
    std::string to_string() const override { return "radiosity patches of " + source_->to_string(); }

private:
    const Shape* source_;
    uint32_t index_;
    bool closed_ = false;
};

RadiosityPatches::RadiosityPatches(const Scene& scene, const RadiositySettings& settings) {
    std::vector<TriangleSoup> soups(scene.shapes().size());
    double total_area = 0.0;
    for (size_t i = 0; i < soups.size(); ++i) {
        scene.shapes()[i]->tessellate(soups[i]);
        for (const auto& t : soups[i].triangles)
            total_area += triangle_area(soups[i].positions[t.x], soups[i].positions[t.y], soups[i].positions[t.z]);
    }
    const float default_patch_area = float(total_area * double(settings.default_area_fraction));
    // Count first: the solve costs patches^2 form factors.
    double estimate = 0.0;
    for (const auto& soup : soups)
        for (const auto& t : soup.triangles)
            estimate += sqr(float(subdivision_for(triangle_area(soup.positions[t.x], soup.positions[t.y], soup.positions[t.z]), settings,
                                                  default_patch_area)));
    if (estimate > double(MaxPatches))
        throw InputError("radiosity: " + std::to_string(size_t(estimate)) + " patches are too many (at most " + std::to_string(MaxPatches) +
                         "); raise max_patch_area or lower subdivisions");

    Properties props("radiosity", SourceLocation{scene.source_file, 0});
    for (size_t i = 0; i < soups.size(); ++i) {
        vertex_offset_.push_back(uint32_t(vertex_count_));
        triangle_offset_.push_back(uint32_t(patch_count_));
        auto mesh =
            std::make_shared<PatchMesh>(props, scene.shapes()[i].get(), uint32_t(i), subdivide(soups[i], settings, default_patch_area));
        vertex_count_ += mesh->positions().size();
        patch_count_ += mesh->triangle_count();
        meshes_.push_back(mesh);
    }
    // Surfaces that only let light through (the `null` BSDF) are invisible: not in the BVH, no
    // elements.
    std::vector<Ref<Shape>> visible;
    for (const auto& mesh : meshes_)
        if (!is_invisible(*static_cast<const PatchMesh&>(*mesh).source())) visible.push_back(mesh);
    accel_.build(visible);
    build_elements(scene);
    build_welds();
}

RadiosityPatches::~RadiosityPatches() = default;

void RadiosityPatches::build_elements(const Scene& scene) {
    front_element_.assign(patch_count_, -1);
    back_element_.assign(patch_count_, -1);
    for (size_t m = 0; m < meshes_.size(); ++m) {
        const auto& mesh = static_cast<const PatchMesh&>(*meshes_[m]);
        const Shape* shape = mesh.source();
        if (is_invisible(*shape)) continue;
        const BSDF& bsdf = *shape->bsdf();
        bool two_sided = bsdf.local_shading().two_sided;
        if (bsdf.flags() != DiffuseReflection &&
            std::find(approximated_.begin(), approximated_.end(), bsdf.to_string()) == approximated_.end())
            approximated_.push_back(bsdf.to_string());
        for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
            // The patch's centre as a ray hit would describe it: uv, shading frame, error bound.
            RayHit centre;
            centre.u = centre.v = 1.0f / 3.0f;
            centre.prim_index = t;
            SurfaceInteraction si;
            mesh.fill_interaction(Ray(), centre, si);
            si.shape = shape;
            Vec3 p0, p1, p2;
            const glm::uvec3& v = mesh.triangles()[t];
            p0 = mesh.positions()[v.x], p1 = mesh.positions()[v.y], p2 = mesh.positions()[v.z];
            for (int side = 0; side < (two_sided ? 2 : 1); ++side) {
                RadiosityElement e;
                e.mesh = uint32_t(m);
                e.triangle = t;
                e.back = side == 1;
                e.area = triangle_area(p0, p1, p2);
                e.centroid = si.p;
                e.normal = e.back ? -si.n : si.n;
                e.p_error = si.p_error;
                si.wi = Vec3(0.0f, 0.0f, e.back ? -1.0f : 1.0f);  // seen head-on from this side
                e.reflectance = glm::clamp(bsdf.albedo(si), Spectrum(0.0f), Spectrum(1.0f));
                if (!all_finite(e.reflectance)) e.reflectance = Spectrum(0.0f);
                if (!e.back && shape->emitter()) e.emitted = Pi * shape->emitter()->eval(si);
                (e.back ? back_element_ : front_element_)[triangle_offset_[m] + t] = int32_t(elements_.size());
                elements_.push_back(e);
            }
        }
    }
}

void RadiosityPatches::build_welds() {
    weld_.resize(vertex_count_);
    for (size_t m = 0; m < meshes_.size(); ++m) {
        const auto& mesh = static_cast<const Mesh&>(*meshes_[m]);
        std::map<std::array<float, 6>, uint32_t> first;  // (position, normal) -> first vertex
        for (size_t v = 0; v < mesh.positions().size(); ++v) {
            const Vec3 &p = mesh.positions()[v], &n = mesh.normals()[v];
            uint32_t global = vertex_offset_[m] + uint32_t(v);
            weld_[global] = first.emplace(std::array<float, 6>{p.x, p.y, p.z, n.x, n.y, n.z}, global).first->second;
        }
    }
}

void RadiosityPatches::triangle(const RadiosityElement& e, Vec3& p0, Vec3& p1, Vec3& p2) const {
    const auto& mesh = static_cast<const Mesh&>(*meshes_[e.mesh]);
    const glm::uvec3& v = mesh.triangles()[e.triangle];
    p0 = mesh.positions()[v.x];
    p1 = mesh.positions()[v.y];
    p2 = mesh.positions()[v.z];
}

bool RadiosityPatches::intersect(const Ray& ray, SurfaceInteraction& si, PatchHit& hit) const {
    RayHit rh;
    const Shape* shape = accel_.intersect(ray, rh);
    si.wi = -ray.d;
    if (!shape) {
        si.shape = nullptr;
        si.t = Infinity;
        return false;
    }
    const auto& mesh = static_cast<const PatchMesh&>(*shape);
    mesh.fill_interaction(ray, rh, si);
    si.wavelengths = ray.wavelengths;
    si.shape = mesh.source();
    si.prim_index = rh.prim_index;
    si.t = rh.t;
    si.wi = si.to_local(-ray.d);
    uint32_t global = triangle_offset_[mesh.index()] + rh.prim_index;
    hit.element = glm::dot(si.n, ray.d) > 0.0f ? back_element_[global] : front_element_[global];
    hit.vertices = mesh.triangles()[rh.prim_index] + glm::uvec3(vertex_offset_[mesh.index()]);
    hit.bary = Vec3(1.0f - rh.u - rh.v, rh.u, rh.v);
    return true;
}

bool RadiosityPatches::occluded_except(const Ray& ray, const Shape* light) const {
    RayHit rh;
    const Shape* shape = accel_.intersect(ray, rh);
    return shape && static_cast<const PatchMesh&>(*shape).source() != light;
}

std::vector<Spectrum> RadiosityPatches::vertex_average(const std::vector<Spectrum>& element_values, bool back) const {
    std::vector<Spectrum> sum(vertex_count_, Spectrum(0.0f));
    std::vector<float> weight(vertex_count_, 0.0f);
    for (size_t i = 0; i < elements_.size(); ++i) {
        const RadiosityElement& e = elements_[i];
        if (e.back != back) continue;
        const glm::uvec3& v = static_cast<const Mesh&>(*meshes_[e.mesh]).triangles()[e.triangle];
        for (int k = 0; k < 3; ++k) {
            uint32_t rep = weld_[vertex_offset_[e.mesh] + v[k]];
            sum[rep] += e.area * element_values[i];
            weight[rep] += e.area;
        }
    }
    std::vector<Spectrum> out(vertex_count_, Spectrum(0.0f));
    for (size_t v = 0; v < vertex_count_; ++v) {
        uint32_t rep = weld_[v];
        if (weight[rep] > 0.0f) out[v] = sum[rep] / weight[rep];
    }
    return out;
}

uint64_t RadiosityPatches::hash() const {
    uint64_t h = 0xcbf29ce484222325ULL;
    for (const auto& shape : meshes_) {
        const auto& mesh = static_cast<const Mesh&>(*shape);
        fnv1a(h, mesh.positions().data(), mesh.positions().size() * sizeof(Vec3));
        fnv1a(h, mesh.triangles().data(), mesh.triangles().size() * sizeof(glm::uvec3));
    }
    for (const RadiosityElement& e : elements_) {
        uint32_t side = e.back ? 1u : 0u;
        fnv1a(h, &side, sizeof side);
        fnv1a(h, &e.reflectance, sizeof e.reflectance);
        fnv1a(h, &e.emitted, sizeof e.emitted);
    }
    return h;
}

std::vector<RadiosityMesh> RadiosityPatches::meshes(const std::vector<Spectrum>& irradiance_front,
                                                    const std::vector<Spectrum>& irradiance_back,
                                                    const std::vector<Spectrum>& radiosity_front) const {
    std::vector<RadiosityMesh> out;
    for (size_t m = 0; m < meshes_.size(); ++m) {
        const auto& mesh = static_cast<const PatchMesh&>(*meshes_[m]);
        RadiosityMesh r;
        r.shape = mesh.source();
        r.patches.positions = mesh.positions();
        r.patches.normals = mesh.normals();
        r.patches.uvs = mesh.uvs();
        r.patches.triangles = mesh.triangles();
        r.patches.closed = mesh.closed();
        auto first = vertex_offset_[m], last = first + uint32_t(mesh.positions().size());
        r.irradiance.assign(irradiance_front.begin() + first, irradiance_front.begin() + last);
        r.radiosity.assign(radiosity_front.begin() + first, radiosity_front.begin() + last);
        if (mesh.triangle_count() > 0 && back_element_[triangle_offset_[m]] >= 0)
            r.irradiance_back.assign(irradiance_back.begin() + first, irradiance_back.begin() + last);
        out.push_back(std::move(r));
    }
    return out;
}

}  // namespace candela
