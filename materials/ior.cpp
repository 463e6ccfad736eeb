#include "materials/ior.h"

#include "core/registry.h"
#include "core/spectral.h"
#include "core/text.h"
#include "materials/ior_data.h"

#include <algorithm>
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
        out["none"] = {"none", {Spectrum(0.0f), Spectrum(1.0f)}};
        for (auto& [name, eta] : eta_text) {
            auto k = k_text.find(name);
            if (k == k_text.end()) continue;
            ComplexIOR ior{spectrum_to_rgb(parse_spd(eta), false, false), spectrum_to_rgb(parse_spd(k->second), false, false)};
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
    eta = std::make_shared<ConstantTexture>(ior->eta);
    k = std::make_shared<ConstantTexture>(ior->k);
}

}  // namespace candela
