#include "materials/ior.h"

#include <algorithm>
#include <map>

namespace candela {

namespace {
std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}
}  // namespace

std::optional<float> named_ior(const std::string& name) {
    // Mitsuba 3's table (include/mitsuba/render/ior.h), values at about 589 nm.
    static const std::map<std::string, float> table = {
        {"vacuum", 1.0f},         {"helium", 1.000036f},       {"hydrogen", 1.000132f},     {"air", 1.000277f},
        {"carbon dioxide", 1.00045f}, {"water", 1.3330f},      {"acetone", 1.36f},          {"ethanol", 1.361f},
        {"carbon tetrachloride", 1.461f}, {"glycerol", 1.4729f}, {"benzene", 1.501f},       {"silicone oil", 1.52045f},
        {"bromine", 1.661f},      {"water ice", 1.31f},        {"fused quartz", 1.458f},    {"pyrex", 1.470f},
        {"acrylic glass", 1.49f}, {"polypropylene", 1.49f},    {"bk7", 1.5046f},            {"sodium chloride", 1.544f},
        {"amber", 1.55f},         {"pet", 1.5750f},            {"diamond", 2.419f},
    };
    auto it = table.find(lower(name));
    if (it == table.end()) return std::nullopt;
    return it->second;
}

float read_ior(const Properties& props, const std::string& param, const std::string& default_name) {
    if (!props.has(param)) return *named_ior(default_name);
    Properties::Type type;
    props.get_raw(param, &type);
    if (type == Properties::Type::String) {
        std::string name = props.get_string(param);
        auto v = named_ior(name);
        if (!v) props.fail(param, "unknown index of refraction \"" + name + "\" (use a number or a name such as bk7, water, air)");
        return *v;
    }
    float v = props.get_float(param);
    if (!(v > 0.0f)) props.fail(param, param + " must be positive");
    return v;
}

float read_relative_ior(const Properties& props, const std::string& default_interior) {
    float int_ior = read_ior(props, "int_ior", default_interior), ext_ior = read_ior(props, "ext_ior", "air");
    if (int_ior == ext_ior) props.fail("int_ior", "int_ior and ext_ior must differ");
    return int_ior / ext_ior;
}

std::optional<ComplexIOR> named_conductor(const std::string& name) {
    // Measured n and k sampled at 650, 550 and 450 nm (the R, G, B wavelengths), from the
    // refractiveindex.info data sets. Mitsuba integrates full spectra against the sRGB colour
    // matching functions instead, so its named metals can differ by a few percent; give eta and
    // k explicitly where an exact match matters.
    static const std::map<std::string, ComplexIOR> table = {
        {"none", {Spectrum(0.0f), Spectrum(1.0f)}},
        {"au", {Spectrum(0.18299f, 0.42108f, 1.37340f), Spectrum(3.42420f, 2.34590f, 1.77040f)}},
        {"ag", {Spectrum(0.15943f, 0.14512f, 0.13547f), Spectrum(3.92910f, 3.19000f, 2.38080f)}},
        {"cu", {Spectrum(0.27105f, 0.67693f, 1.31640f), Spectrum(3.60920f, 2.62480f, 2.29210f)}},
        {"al", {Spectrum(1.34560f, 0.96521f, 0.61722f), Spectrum(7.47460f, 6.39950f, 5.30310f)}},
        {"cr", {Spectrum(3.10710f, 3.18120f, 2.32300f), Spectrum(3.33140f, 3.32910f, 3.13500f)}},
    };
    auto it = table.find(lower(name));
    if (it == table.end()) return std::nullopt;
    return it->second;
}

}  // namespace candela

namespace candela {

void read_conductor_ior(const Properties& props, Ref<Texture>& eta, Ref<Texture>& k) {
    bool explicit_ior = props.has("eta") || props.has("k");
    if (explicit_ior && props.has("material")) props.fail("material", "give either a material or eta and k, not both");
    if (explicit_ior) {
        eta = props.get_texture("eta", Spectrum(0.0f));
        k = props.get_texture("k", Spectrum(1.0f));
        return;
    }
    std::string name = props.get_string("material", "none");
    auto ior = named_conductor(name);
    if (!ior) props.fail("material", "unknown conductor \"" + name + "\" (known: none, Au, Ag, Cu, Al, Cr)");
    eta = std::make_shared<ConstantTexture>(ior->eta);
    k = std::make_shared<ConstantTexture>(ior->k);
}

}  // namespace candela
