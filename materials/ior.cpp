#include "materials/ior.h"

#include "core/registry.h"
#include "core/spectral.h"
#include "core/text.h"
#include "materials/ior_data.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace candela {

std::optional<float> named_ior(const std::string& name) {
    // Mitsuba 3's table (include/mitsuba/render/ior.h), values at about 589 nm.
    static const std::map<std::string, float> table = {
        {"vacuum", 1.0f},      {"helium", 1.000036f},        {"hydrogen", 1.000132f},
        {"air", 1.000277f},    {"carbon dioxide", 1.00045f}, {"water", 1.3330f},
        {"acetone", 1.36f},    {"ethanol", 1.361f},          {"carbon tetrachloride", 1.461f},
        {"glycerol", 1.4729f}, {"benzene", 1.501f},          {"silicone oil", 1.52045f},
        {"bromine", 1.661f},   {"water ice", 1.31f},         {"fused quartz", 1.458f},
        {"pyrex", 1.470f},     {"acrylic glass", 1.49f},     {"polypropylene", 1.49f},
        {"bk7", 1.5046f},      {"sodium chloride", 1.544f},  {"amber", 1.55f},
        {"pet", 1.5750f},      {"diamond", 2.419f},
    };
    auto it = table.find(to_lower(name));
    if (it == table.end()) {
        if (const SellmeierGlass* glass = named_glass(name)) return float(glass->ior(589.3));
        return std::nullopt;
    }
    return it->second;
}

double SellmeierGlass::ior(double lambda_nm) const {
    const double l2 = (lambda_nm * 1e-3) * (lambda_nm * 1e-3);
    double n2 = 1.0;
    for (int i = 0; i < 3; ++i) n2 += B[i] * l2 / (l2 - C[i]);
    return std::sqrt(n2);
}

const SellmeierGlass* named_glass(const std::string& name) {
    // Schott's catalogue (N-BK7, N-BAF10, F2, SF11) and Malitson 1965 (fused silica, C = the
    // square of his resonance wavelengths 0.0684043, 0.1162414 and 9.896161 um).
    static const SellmeierGlass glasses[] = {
        {"glass-BK7", {1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653}},
        {"glass-BAF10", {1.5851495, 0.143559385, 1.08521269}, {0.00926681282, 0.0424489805, 105.613573}},
        {"glass-F2", {1.34533359, 0.209073176, 0.937357162}, {0.00997743871, 0.0470450767, 111.886764}},
        {"glass-SF11", {1.73759695, 0.313747346, 1.89878101}, {0.013188707, 0.0623068142, 155.23629}},
        {"glass-fused-silica", {0.6961663, 0.4079426, 0.8974794}, {0.0684043 * 0.0684043, 0.1162414 * 0.1162414, 9.896161 * 9.896161}},
    };
    for (const SellmeierGlass& g : glasses)
        if (to_lower(name) == to_lower(g.name)) return &g;
    return nullptr;
}

float SpectralIOR::at(float lambda_nm) const {
    if (glass) return float(glass->ior(lambda_nm));
    if (samples && !samples->spectrum().wavelengths.empty()) return float(samples->spectrum().at(lambda_nm));
    return value;
}

SpectralIOR read_spectral_ior(const Properties& props, const std::string& param, const std::string& default_name) {
    SpectralIOR ior;
    if (auto measured = props.measured_spectrum(param)) {
        props.get_texture(param);  // marks it used
        ior.samples = measured;
        ior.value = float(measured->spectrum().at(589.3));
        const SampledSpectrum& s = measured->spectrum();
        for (double v : s.values)
            if (!(v > 0.0)) props.fail(param, param + " must be positive at every wavelength");
        if (!(s.wavelengths.front() <= CieMin && s.wavelengths.back() >= CieMax))
            props.fail(param, param + " must cover the visible range 360-830 nm (it is sampled there)");
        return ior;
    }
    ior.value = read_ior(props, param, default_name);
    Properties::Type type;
    if (props.has(param) && (props.get_raw(param, &type), type == Properties::Type::String))
        ior.glass = named_glass(props.get_string(param));
    return ior;
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
    return int_ior / ext_ior;
}

namespace {
// Every named conductor, computed once from the embedded .spd text (materials/ior_data.h).
const std::map<std::string, std::pair<std::string, ComplexIOR>>& conductor_table() {
    static const std::map<std::string, std::pair<std::string, ComplexIOR>> table = [] {
        std::map<std::string, const char*> eta_text, k_text;
        for (const EmbeddedFile& f : ior_data_files()) {
            std::string file = f.name;
            auto take = [&](const std::string& suffix, std::map<std::string, const char*>& into) {
                if (file.size() > suffix.size() && file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0)
                    into[file.substr(0, file.size() - suffix.size())] = f.text;
            };
            take(".eta.spd", eta_text);
            take(".k.spd", k_text);
        }
        std::map<std::string, std::pair<std::string, ComplexIOR>> out;
        out["none"] = {"none", {Spectrum(0.0f), Spectrum(1.0f), {}, {}}};
        for (auto& [name, eta] : eta_text) {
            auto k = k_text.find(name);
            if (k == k_text.end()) continue;
            SampledSpectrum eta_spectrum = parse_spd(eta), k_spectrum = parse_spd(k->second);
            ComplexIOR ior{spectrum_to_rgb(eta_spectrum, false, false), spectrum_to_rgb(k_spectrum, false, false), eta_spectrum,
                           k_spectrum};
            out[to_lower(name)] = {name, ior};
        }
        return out;
    }();
    return table;
}
}  // namespace

std::optional<ComplexIOR> named_conductor(const std::string& name) {
    auto it = conductor_table().find(to_lower(name));
    if (it == conductor_table().end()) return std::nullopt;
    return it->second.second;
}

std::vector<std::string> named_conductors() {
    std::vector<std::string> names;
    for (auto& [key, entry] : conductor_table()) names.push_back(entry.first);
    std::sort(names.begin(), names.end());
    return names;
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
    if (!ior) {
        std::string known;
        for (auto& n : named_conductors()) known += (known.empty() ? "" : ", ") + n;
        props.fail("material", "unknown conductor \"" + name + "\" (nearest: \"" + nearest_name(name, named_conductors()) +
                                   "\") (known: " + known + ")");
    }
    // Measured: the spectral variant uses the spectra themselves, per wavelength.
    auto constant = [](const Spectrum& rgb, const SampledSpectrum& spectrum) -> Ref<Texture> {
        if (spectrum.wavelengths.empty()) return std::make_shared<ConstantTexture>(rgb);
        return std::make_shared<SpectrumTexture>(rgb, spectrum);
    };
    eta = constant(ior->eta, ior->eta_spectrum);
    k = constant(ior->k, ior->k_spectrum);
}

}  // namespace candela
