#include "tests/probe.h"

#include "core/bsdf.h"
#include "core/registry.h"

namespace candela::test {

std::map<std::string, Properties>& probes() {
    static std::map<std::string, Properties> p;
    return p;
}

namespace {
class ProbeBSDF final : public BSDF {
public:
    explicit ProbeBSDF(const Properties& props) {
        for (const auto& name : props.names()) props.get_raw(name);
        probes()[props.id] = props;
        flags_ = DiffuseReflection;
    }
    BSDFSample sample(const BSDFContext&, const SurfaceInteraction&, float, const Vec2&) const override { return {}; }
    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    Spectrum albedo(const SurfaceInteraction&) const override { return Spectrum(0.0f); }
};
CANDELA_REGISTER(ProbeBSDF, ObjectKind::BSDF, "test_probe");
}  // namespace

}  // namespace candela::test
