// rawconstant: one value everywhere, used as given: no colour space, no spectral upsampling, no
// check that it is a reflectance. Mitsuba 3's texture for data that are not colours, such as the
// normal of a normal map (value 0.5, 0.5, 1 is the identity map) or a roughness.
//
// Parameters (Mitsuba 3):
//   value   float or vector   the value (required); a float is the same in every channel

#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"

namespace candela {

namespace {

Spectrum raw_value(const Properties& props) {
    if (!props.has("value")) props.fail("rawconstant needs its value: a float or a 3D vector (<vector name=\"value\" .../>)");
    Properties::Type type;
    const Properties::Value& value = props.get_raw("value", &type);
    if (type == Properties::Type::Float) return Spectrum(float(std::get<double>(value)));
    if (type == Properties::Type::Integer) return Spectrum(float(std::get<int64_t>(value)));
    if (type == Properties::Type::Vector || type == Properties::Type::Point) return std::get<Vec3>(value);
    props.fail("value",
               "rawconstant's value is a float or a 3D vector, not a colour (<vector name=\"value\" x=... /> or value=\"x, y, z\")");
}

}  // namespace

class RawConstantTexture final : public ConstantTexture {
public:
    explicit RawConstantTexture(const Properties& props) : ConstantTexture(raw_value(props)) {}
    std::string to_string() const override { return "rawconstant"; }
};

CANDELA_REGISTER_SPECTRAL(RawConstantTexture, ObjectKind::Texture, "rawconstant");

}  // namespace candela
