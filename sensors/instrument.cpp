#include "sensors/instrument.h"

#include "core/error.h"
#include "core/film.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/warning.h"

#include <algorithm>

namespace candela {

Instrument::Instrument(const Properties& props) : Sensor(props) {
    const Vec2i size = film_->full_size();
    if (size != Vec2i(1, 1)) {
        SourceLocation where = film_->location().file.empty() ? props.location() : film_->location();
        throw SceneError(where, "the " + props.plugin_type() + " sensor measures one value: its film must be 1 x 1 pixel, not " +
                                    std::to_string(size.x) + " x " + std::to_string(size.y) +
                                    " (<integer name=\"width\" value=\"1\"/> and height)");
    }
    if (film_->filter().radius() > 0.5f + 1e-4f)
        warn(props.location(), "the " + props.plugin_type() +
                                   " sensor should have a reconstruction filter of radius 0.5 or less (the default box): a wider "
                                   "one weights its single pixel's samples unevenly");
}

bool Instrument::aim() {
    Vec3 d = to_world_.apply_vector(Vec3(0.0f, 0.0f, 1.0f));
    if (!to_world_.all_finite() || !(squared_length(d) > 0.0f)) return false;
    direction_ = glm::normalize(d);
    return true;
}

void Instrument::traverse(ParameterVisitor& visitor) {
    expose_transform(visitor, "to_world", to_world_);
    visitor.object("film", film_.get());
}

void Instrument::parameters_changed(const std::vector<std::string>& keys) {
    if (std::find(keys.begin(), keys.end(), "to_world") != keys.end() && !aim())
        throw InputError("the " + to_string() + " sensor's to_world must be finite and keep its +z direction");
}

void Instrument::set_film_size(const Vec2i& size) {
    if (size != Vec2i(1, 1)) throw InputError("the " + to_string() + " sensor's slice of a batch must be 1 x 1 pixel");
}

}  // namespace candela
