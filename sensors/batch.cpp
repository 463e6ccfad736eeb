// batch: several sensors rendered side by side into one film (Mitsuba 3's `batch` sensor).
//
// Parameters:
//   (nested sensors)   the sub-sensors, in order, or shapes each carrying a sensor (an
//                      irradiancemeter); at least one
//   srf                spectrum   the spectral variant's sensor response (as every sensor's)
//   film, sampler      nested, as every sensor's: the batch's own film, whose width must be a
//                      multiple of the number of sub-sensors; shutter_open and shutter_close
//                      are the batch's too
//
// Sub-sensor i renders into the i-th slice of the film's width (columns i w / n to
// (i + 1) w / n): each takes its slice's size (keeping its field of view along x, as Mitsuba's
// set_size keeps x_fov) and the batch's film, sampler and shutter replace its own. A sample whose
// filter reaches across a slice's edge splats into the neighbouring slice, as in Mitsuba. The
// particle tracer refuses it (Mitsuba's documentation says the same).

#include "core/error.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sensor.h"
#include "core/shape.h"

#include <cmath>

namespace candela {

class BatchSensor final : public Sensor {
public:
    explicit BatchSensor(const Properties& props) : Sensor(props) {
        // Sensors and shapes with a sensor, in document order.
        std::vector<std::pair<std::string, Ref<Object>>> children = props.get_named_objects(ObjectKind::Sensor);
        for (auto& [name, shape] : props.get_named_objects(ObjectKind::Shape)) {
            auto& attached = std::static_pointer_cast<Shape>(shape)->attached_sensor();
            if (!attached) props.fail(name, "a batch's shapes must each carry a sensor (an irradiancemeter)");
            children.emplace_back(name, attached);
            shapes_.push_back(std::static_pointer_cast<Shape>(shape));
        }
        for (const std::string& name : props.names())
            for (auto& [child_name, child] : children)
                if (child_name == name) {
                    sensors_.push_back(std::static_pointer_cast<Sensor>(child));
                    names_.push_back(child->id.empty() ? "sensor" + std::to_string(sensors_.size() - 1) : child->id);
                    locations_.push_back(props.location_of(name));
                }
        if (sensors_.empty()) props.fail("a batch sensor needs at least one sensor nested in it");
        const Vec2i size = film_->full_size();
        const int n = int(sensors_.size());
        if (size.x % n != 0)
            props.fail("the batch's film width (" + std::to_string(size.x) + ") must be a multiple of its number of sensors (" +
                       std::to_string(n) + ")");
        slice_width_ = size.x / n;
        for (size_t i = 0; i < sensors_.size(); ++i) {
            try {
                sensors_[i]->set_film_size(Vec2i(slice_width_, size.y));
            } catch (const InputError& e) {
                throw SceneError(locations_[i], e.what());
            }
        }
    }

    Ray sample_ray(const Vec2& film_pos, const Vec2& aperture_u, float time) const override {
        int i = slice_of(film_pos);
        return sensors_[size_t(i)]->sample_ray(film_pos - Vec2(float(i * slice_width_), 0.0f), aperture_u, time);
    }
    float sample_weight(const Vec2& film_pos) const override {
        int i = slice_of(film_pos);
        return sensors_[size_t(i)]->sample_weight(film_pos - Vec2(float(i * slice_width_), 0.0f));
    }

    void set_scene(const Scene& scene) override {
        for (auto& sensor : sensors_) sensor->set_scene(scene);
    }
    bool is_animated() const override {
        for (auto& sensor : sensors_)
            if (sensor->is_animated()) return true;
        return false;
    }
    // A batch's pixel belongs to one sub-sensor; a packet may straddle two slices' edge (a few
    // packets of a film's rows: rays of two frusta, traced correctly, only slower).
    bool rays_coherent() const override {
        for (auto& sensor : sensors_)
            if (!sensor->rays_coherent()) return false;
        return true;
    }
    SourceLocation motion_location() const override {
        for (auto& sensor : sensors_)
            if (sensor->is_animated()) return sensor->motion_location();
        return {};
    }

    // Each sub-sensor by its id, or "sensor<i>" when it has none (Mitsuba's names).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("film", film_.get());
        for (size_t i = 0; i < sensors_.size(); ++i) visitor.object(names_[i], sensors_[i].get());
    }

    std::string to_string() const override { return "batch"; }

private:
    int slice_of(const Vec2& film_pos) const {
        int i = int(std::floor(film_pos.x / float(slice_width_)));
        return std::min(std::max(i, 0), int(sensors_.size()) - 1);
    }

    std::vector<Ref<Sensor>> sensors_;
    std::vector<std::string> names_;
    std::vector<SourceLocation> locations_;
    std::vector<Ref<Shape>> shapes_;  // the shapes of nested irradiancemeters, kept alive
    int slice_width_ = 1;
};

CANDELA_REGISTER(BatchSensor, ObjectKind::Sensor, "batch");

}  // namespace candela
