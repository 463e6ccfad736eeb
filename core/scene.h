#pragma once
// The scene: shapes in one Embree BVH, their BSDFs, the emitters, the sensor and the integrator.
// Built by the loader from a scene file; read-only while rendering.

#include "core/accel.h"
#include "core/emitter.h"
#include "core/integrator.h"
#include "core/rng.h"
#include "core/sensor.h"

#include <map>
#include <string>
#include <vector>

namespace candela {

struct MuellerSpectrum;

// The most surfaces with a Null lobe (null, mask, polarizer) that one ray crosses without
// scattering: a shadow ray, or a path between two scattering vertices. A ray that keeps meeting
// such surfaces (coplanar layers the ray offsets cannot separate, a degenerate stack) is taken as
// blocked rather than followed forever.
constexpr int MaxNullCrossings = 256;

class Scene : public Object {
public:
    // `sensor_index`: which of the scene's sensors it renders (Mitsuba's `mitsuba -s N`; 0, the
    // first in the file, by default). The others are built too, so that their errors show.
    explicit Scene(const Properties& props, int sensor_index = 0);
    ObjectKind kind() const override { return ObjectKind::Scene; }

    // Closest surface along the ray; si.is_valid() is false for a miss.
    bool intersect(const Ray& ray, SurfaceInteraction& si) const;
    bool occluded(const Ray& ray) const { return accel_.occluded(ray); }
    // The same for a batch of rays at once, traced as Embree packets (a wavefront): found[i] and
    // si[i] as intersect(*rays[i], *si[i]) gives them, blocked[i] as occluded(*rays[i]).
    // `coherent`: each packet's rays run nearly together (Accel::intersect_packet's).
    void intersect_batch(const Ray* const rays[], SurfaceInteraction* const si[], bool found[], size_t n, bool coherent = false) const;
    void occluded_batch(const Ray* const rays[], bool blocked[], size_t n) const;
    // Whether a surface has a Null lobe (null, mask, polarizer): then shadow rays need
    // transmittance(), not only occluded().
    bool has_null_surfaces() const { return has_null_surfaces_; }
    // The fraction of light that travels along the shadow ray unblocked: 0 or 1 from one any-hit
    // query, unless the scene has surfaces with a Null lobe (null, mask, polarizer); then the
    // product of the null_transmission() of every surface the ray crosses (0 at an opaque one).
    // With `crossed` (the polarized variant) also the product, from the ray's origin outward, of
    // the crossed surfaces' normalised Mueller matrices (for light travelling back along the ray;
    // normalized_world_mueller of their Null lobe): the identity when the ray crosses none.
    Spectrum transmittance(const Ray& ray, MuellerSpectrum* crossed = nullptr) const;
    // The same for a shadow ray that starts in `medium` (null: vacuum): each stretch also takes
    // its medium's transmittance (ratio tracking draws from `rng`), and the medium changes where
    // the ray crosses a shape with an interior or exterior medium.
    Spectrum transmittance(const Ray& ray, const Medium* medium, PCG32& rng, MuellerSpectrum* crossed = nullptr) const;
    // Whether any shape or the sensor carries a participating medium.
    bool has_media() const { return has_media_; }
    // Whether a shape, the sensor or an emitter has an animated to_world (motion blur).
    bool is_animated() const { return is_animated_; }
    // Where the first animated to_world is given (when is_animated()).
    const SourceLocation& motion_location() const { return motion_location_; }

    const std::vector<Ref<Shape>>& shapes() const { return shapes_; }
    // All emitters: area emitters of shapes, then the others in document order.
    const std::vector<Ref<Emitter>>& emitters() const { return emitters_; }
    const std::vector<const Emitter*>& infinite_emitters() const { return infinite_emitters_; }
    // Radiance from all infinite emitters along an escaped ray.
    Spectrum eval_environment(const Vec3& d, const Wavelengths* wavelengths = nullptr, float time = 0.0f) const;

    Sensor& sensor() const { return *sensors_[size_t(sensor_index_)]; }
    // The scene file's sensors (1 for a scene that declares none: the default camera), and which
    // of them sensor() is.
    int sensor_count() const { return int(sensors_.size()); }
    int sensor_index() const { return sensor_index_; }
    // Sensor `index` (below sensor_count()), as the file describes it: only sensor() is prepared
    // for rendering (its film and sampler sized, its scene set). Python's scene.sensors() reads
    // the others.
    const Sensor& sensor_at(int index) const { return *sensors_.at(size_t(index)); }
    Integrator& integrator() const { return *integrator_; }
    const Ref<Integrator>& integrator_ref() const { return integrator_; }
    void set_integrator(Ref<Integrator> integrator) { integrator_ = std::move(integrator); }
    const BoundingBox& bbox() const { return bbox_; }
    const Accel& accel() const { return accel_; }
    // After shapes changed (core/parameters.h): the bounds, the BVH (rebuilt) and what the
    // emitters derive from the scene's bounds.
    void update_geometry();

    // The variant it was loaded for (core/variant.h): the spectral variant samples wavelengths.
    Variant variant() const { return variant_; }
    bool spectral() const { return variant_ != Variant::ScalarRGB; }
    bool polarized() const { return variant_ == Variant::ScalarSpectralPolarized; }

    std::string source_file;  // the scene file it was loaded from
    // The scene file's parameters after <default>s and -D overrides, substituted ($name) as
    // everywhere else; analytic scenes state their exact answer as the parameter "expected".
    std::map<std::string, std::string> parameters;
    // The other files the scene read (included scene files, meshes, textures, spectra), in the
    // order they were first found.
    std::vector<std::string> input_files;

private:
    // intersect()'s answer from the accelerator's: the interaction of `shape` (null: a miss) hit by `ray`.
    static bool interaction_of_hit(const Ray& ray, const Shape* shape, const RayHit& hit, SurfaceInteraction& si);

    Variant variant_ = Variant::ScalarRGB;
    std::vector<Ref<Shape>> shapes_;
    std::vector<Ref<Emitter>> emitters_;
    std::vector<const Emitter*> infinite_emitters_;
    std::vector<Ref<Sensor>> sensors_;
    int sensor_index_ = 0;  // which of sensors_ sensor() is
    Ref<Integrator> integrator_;
    BoundingBox bbox_;
    Accel accel_;
    bool has_null_surfaces_ = false;
    bool has_media_ = false;
    bool is_animated_ = false;
    SourceLocation motion_location_;
};

}  // namespace candela
