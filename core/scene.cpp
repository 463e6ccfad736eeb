#include "core/scene.h"

#include "core/bsdf.h"
#include "core/medium.h"
#include "core/mueller.h"
#include "core/registry.h"

#include <algorithm>

namespace candela {

Scene::Scene(const Properties& props, int sensor_index) {
    source_file = props.location().file;
    variant_ = props.variant();
    // Shape groups are not drawn themselves, only through the instances that reference them.
    for (auto& obj : props.get_objects(ObjectKind::Shape)) {
        auto shape = std::static_pointer_cast<Shape>(obj);
        if (!shape->is_shape_group()) shapes_.push_back(shape);
    }
    // Area emitters first (in shape order), then the scene's own emitters.
    for (auto& shape : shapes_) shape->collect_emitters(emitters_);
    for (auto& obj : props.get_objects(ObjectKind::Emitter)) {
        auto emitter = std::static_pointer_cast<Emitter>(obj);
        if (emitter->type() == EmitterType::Area) {
            // An area emitter declared at the top with an id and referenced from its shape (as
            // Mitsuba allows) is already in the list; one that no shape names is an error.
            bool attached = std::find(emitters_.begin(), emitters_.end(), emitter) != emitters_.end();
            if (!attached) throw SceneError(props.location_of(emitter->id), "an area emitter must be nested inside a shape");
            continue;
        }
        emitters_.push_back(emitter);
    }
    // The scene's own sensors in document order, then those nested in shapes, in shape order
    // (the order Mitsuba 3.8 numbers them in, `mitsuba -s N`).
    for (auto& sensor : props.get_objects(ObjectKind::Sensor)) sensors_.push_back(std::static_pointer_cast<Sensor>(sensor));
    for (auto& shape : shapes_)
        if (auto& attached = shape->attached_sensor()) sensors_.push_back(attached);
    if (sensors_.empty()) sensors_.push_back(create_plugin_as<Sensor>(ObjectKind::Sensor, Properties("perspective", props.location())));
    // The second one is the mistake: its line, not the scene's.
    auto second = [&](ObjectKind kind) { return props.location_of(props.get_named_objects(kind)[1].first); };
    const int sensor_count = int(sensors_.size());
    if (sensor_index < 0 || sensor_index >= sensor_count)
        throw SceneError(
            props.location(),
            "sensor index " + std::to_string(sensor_index) + " is out of range: the scene has " + std::to_string(sensor_count) +
                (sensor_count == 1 ? " sensor (index 0)" : " sensors (indices 0 to " + std::to_string(sensor_count - 1) + ")"));
    sensor_index_ = sensor_index;
    Sensor& sensor = this->sensor();
    auto integrators = props.get_objects(ObjectKind::Integrator);
    if (integrators.size() > 1) throw SceneError(second(ObjectKind::Integrator), "only one integrator per scene is supported");
    integrator_ = integrators.empty() ? create_plugin_as<Integrator>(ObjectKind::Integrator, Properties("path", props.location()))
                                      : std::static_pointer_cast<Integrator>(integrators[0]);
    // Top-level BSDFs, textures, samplers, films and filters exist to be referenced by id (Mitsuba's
    // documentation scenes declare their sampler at the top and refer to it from the sensor).
    for (ObjectKind kind : {ObjectKind::BSDF, ObjectKind::Texture, ObjectKind::Sampler, ObjectKind::Film, ObjectKind::Filter,
                            ObjectKind::Medium, ObjectKind::Phase, ObjectKind::Volume})
        props.get_objects(kind);

    for (auto& shape : shapes_) {
        bbox_.expand(shape->bbox());
        if (shape->bsdf()->has_null_lobe()) has_null_surfaces_ = true;
        if (shape->is_medium_transition()) has_media_ = true;
    }
    if (sensor.medium()) has_media_ = true;
    const float shutter_close = sensor.shutter_open() + sensor.shutter_open_time();
    // The first animation in the scene, for the message of an integrator that renders none.
    auto note_motion = [&](bool animated, const SourceLocation& where) {
        if (animated && !is_animated_) motion_location_ = where;
        is_animated_ = is_animated_ || animated;
    };
    for (auto& shape : shapes_) {
        shape->set_shutter(sensor.shutter_open(), shutter_close);
        note_motion(shape->is_animated(), shape->motion_location());
    }
    note_motion(sensor.is_animated(), sensor.motion_location());
    for (auto& emitter : emitters_) note_motion(emitter->is_animated(), emitter->motion_location());
    accel_.set_shutter(sensor.shutter_open(), shutter_close);
    accel_.build(shapes_);
    for (auto& emitter : emitters_) {
        emitter->set_scene(*this);
        if (emitter->is_infinite()) infinite_emitters_.push_back(emitter.get());
    }
    sensor.set_scene(*this);
}

void Scene::update_geometry() {
    bbox_ = BoundingBox();
    for (auto& shape : shapes_) bbox_.expand(shape->bbox());
    accel_.build(shapes_);
    for (auto& emitter : emitters_) emitter->set_scene(*this);
    sensor().set_scene(*this);
}

bool Scene::intersect(const Ray& ray, SurfaceInteraction& si) const {
    RayHit hit;
    return interaction_of_hit(ray, accel_.intersect(ray, hit), hit, si);
}

bool Scene::interaction_of_hit(const Ray& ray, const Shape* shape, const RayHit& hit, SurfaceInteraction& si) {
    si.time = ray.time;
    si.wavelengths = ray.wavelengths;
    if (!shape) {
        si.shape = nullptr;
        si.t = Infinity;
        si.wi = -ray.d;
        return false;
    }
    // An instance replaces si.shape by the shape of its group that was hit (for its BSDF).
    si.shape = shape;
    shape->fill_interaction(ray, hit, si);
    si.prim_index = hit.prim_index;
    si.prim_uv = Vec2(hit.u, hit.v);
    si.t = hit.t;
    si.wi = si.to_local(-ray.d);
    return true;
}

void Scene::intersect_batch(const Ray* const rays[], SurfaceInteraction* const si[], bool found[], size_t n, bool coherent) const {
    const Shape* shapes[Accel::PacketSize];
    RayHit hits[Accel::PacketSize];
    for (size_t first = 0; first < n; first += Accel::PacketSize) {
        const size_t count = std::min(Accel::PacketSize, n - first);
        accel_.intersect_packet(rays + first, count, shapes, hits, coherent);
        for (size_t i = 0; i < count; ++i) found[first + i] = interaction_of_hit(*rays[first + i], shapes[i], hits[i], *si[first + i]);
    }
}

void Scene::occluded_batch(const Ray* const rays[], bool blocked[], size_t n) const {
    for (size_t first = 0; first < n; first += Accel::PacketSize)
        accel_.occluded_packet(rays + first, std::min(Accel::PacketSize, n - first), blocked + first);
}

Spectrum Scene::transmittance(const Ray& shadow_ray, MuellerSpectrum* crossed) const {
    if (!has_null_surfaces_) {
        if (crossed) *crossed = identity_spectrum();
        return occluded(shadow_ray) ? Spectrum(0.0f) : Spectrum(1.0f);
    }
    PCG32 unused;
    return transmittance(shadow_ray, nullptr, unused, crossed);
}

Spectrum Scene::transmittance(const Ray& shadow_ray, const Medium* medium, PCG32& rng, MuellerSpectrum* mueller) const {
    if (mueller) *mueller = identity_spectrum();
    // Cross the surfaces one by one, at most MaxNullCrossings of them.
    Spectrum T(1.0f);
    Ray ray = unit_direction(shadow_ray);  // distances along it are measured below
    for (int crossed = 0;; ++crossed) {
        SurfaceInteraction si;
        bool found = intersect(ray, si);
        if (medium) T *= medium->transmittance(ray, found ? si.t : ray.tmax, rng);
        if (!found || is_black(T)) return T;
        if (crossed == MaxNullCrossings) return Spectrum(0.0f);
        const BSDF& bsdf = *si.shape->bsdf();
        T *= bsdf.null_transmission(si);
        if (is_black(T)) return T;
        if (mueller) {
            BSDFContext ctx;
            ctx.lobes = Null;
            multiply_by_bsdf(*mueller, bsdf, ctx, si, -si.wi, Null);
        }
        if (si.shape->is_medium_transition()) medium = si.shape->target_medium(si, ray.d);
        Vec3 origin = offset_ray_origin(si.p, si.p_error, si.n, ray.d);
        float remaining = ray.tmax - glm::dot(origin - ray.o, ray.d);  // inf stays inf
        if (!(remaining > 0.0f)) return T;
        const float time = ray.time;
        Wavelengths* wavelengths = ray.wavelengths;
        ray = Ray(origin, ray.d, remaining);
        ray.time = time;
        ray.wavelengths = wavelengths;
    }
}

Spectrum Scene::eval_environment(const Vec3& d, const Wavelengths* wavelengths, float time) const {
    Spectrum L(0.0f);
    for (const Emitter* e : infinite_emitters_) L += e->eval_environment(d, wavelengths, time);
    return L;
}

}  // namespace candela
