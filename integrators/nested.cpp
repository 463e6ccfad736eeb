#include "integrators/nested.h"

#include "core/properties.h"

namespace candela {

std::vector<NestedIntegrator> read_nested_integrators(const Properties& props) {
    std::vector<NestedIntegrator> nested;
    for (auto& [name, object] : props.get_named_objects(ObjectKind::Integrator)) {
        auto integrator = std::dynamic_pointer_cast<SamplingIntegrator>(object);
        if (!integrator)
            props.fail(props.plugin_type() + " can nest only sampling integrators (path, direct, aov, ...), not " + object->to_string());
        nested.push_back({name, integrator, integrator->channel_names()});
    }
    return nested;
}

Spectrum sample_nested(const NestedIntegrator& nested, const Scene& scene, Sampler& sampler, const Ray& ray, const SampleRecord& outer,
                       SampleRecord& record, bool with_first_hit) {
    record.film_pos = outer.film_pos;
    record.aperture = outer.aperture;
    record.differential_scale = outer.differential_scale;
    record.first_hit = with_first_hit ? outer.first_hit : nullptr;
    record.valid = false;
    return nested.integrator->sample_radiance(scene, sampler, ray, record);
}

}  // namespace candela
