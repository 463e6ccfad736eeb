#include "core/properties.h"

#include "core/file_resolver.h"
#include "core/text.h"
#include "core/texture.h"
#include "core/warning.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>

namespace candela {

const char* kind_tag(ObjectKind kind) {
    switch (kind) {
        case ObjectKind::Scene: return "scene";
        case ObjectKind::Shape: return "shape";
        case ObjectKind::BSDF: return "bsdf";
        case ObjectKind::Emitter: return "emitter";
        case ObjectKind::Texture: return "texture";
        case ObjectKind::Sensor: return "sensor";
        case ObjectKind::Film: return "film";
        case ObjectKind::Filter: return "rfilter";
        case ObjectKind::Sampler: return "sampler";
        case ObjectKind::Integrator: return "integrator";
        case ObjectKind::Medium: return "medium";
        case ObjectKind::Phase: return "phase";
        case ObjectKind::Volume: return "volume";
    }
    return "object";
}

const char* type_name(Properties::Type t) {
    switch (t) {
        case Properties::Type::Integer: return "integer";
        case Properties::Type::Float: return "float";
        case Properties::Type::Boolean: return "boolean";
        case Properties::Type::String: return "string";
        case Properties::Type::Point: return "point";
        case Properties::Type::Vector: return "vector";
        case Properties::Type::RGB: return "rgb";
        case Properties::Type::Transform: return "transform";
        case Properties::Type::Object: return "object";
        case Properties::Type::Animation: return "animation";
    }
    return "?";
}

void Properties::set(const std::string& name, Type type, Value value, const SourceLocation& where) {
    auto it = entries_.find(name);
    if (it != entries_.end())
        throw SceneError(where, "property \"" + name + "\" was already specified (at " + it->second.where.str() + ")");
    entries_.emplace(name, Entry{type, std::move(value), where, entries_.size()});
}

void Properties::fail(const std::string& name, const std::string& message) const { throw SceneError(location_of(name), message); }

void Properties::fail(const std::string& message) const { throw SceneError(location_, message); }

SourceLocation Properties::location_of(const std::string& name) const {
    auto it = entries_.find(name);
    return it == entries_.end() ? location_ : it->second.where;
}

const Properties::Entry* Properties::find(const std::string& name, Type expected) const {
    asked_.insert(name);
    auto it = entries_.find(name);
    if (it == entries_.end()) return nullptr;
    const Entry& e = it->second;
    bool ok = e.type == expected || (expected == Type::Float && e.type == Type::Integer) ||
              (expected == Type::RGB && (e.type == Type::Float || e.type == Type::Integer)) ||
              (expected == Type::Point && e.type == Type::Vector) || (expected == Type::Vector && e.type == Type::Point);
    if (!ok)
        throw SceneError(e.where, "property \"" + name + "\" of " + plugin_type_ + " has type " + type_name(e.type) + ", expected " +
                                      type_name(expected));
    e.used = true;
    return &e;
}

const Properties::Entry& Properties::require(const std::string& name, Type expected) const {
    const Entry* e = find(name, expected);
    if (!e) throw SceneError(location_, plugin_type_ + ": missing required property \"" + name + "\" (" + type_name(expected) + ")");
    return *e;
}

static double as_double(const Properties::Value& v) {
    if (auto i = std::get_if<int64_t>(&v)) return double(*i);
    return std::get<double>(v);
}

int Properties::get_int(const std::string& name) const {
    const Entry& e = require(name, Type::Integer);
    return checked_int(name, std::get<int64_t>(e.value));
}
int Properties::get_int(const std::string& name, int def) const {
    const Entry* e = find(name, Type::Integer);
    return e ? checked_int(name, std::get<int64_t>(e->value)) : def;
}
int Properties::checked_int(const std::string& name, int64_t value) const {
    if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
        fail(name, name + " = " + std::to_string(value) + " lies beyond the integers Candela reads (" +
                       std::to_string(std::numeric_limits<int>::min()) + " to " + std::to_string(std::numeric_limits<int>::max()) + ")");
    return int(value);
}
float Properties::get_float(const std::string& name) const { return float(as_double(require(name, Type::Float).value)); }
float Properties::get_float(const std::string& name, float def) const {
    const Entry* e = find(name, Type::Float);
    return e ? float(as_double(e->value)) : def;
}
bool Properties::get_bool(const std::string& name, bool def) const {
    const Entry* e = find(name, Type::Boolean);
    return e ? std::get<bool>(e->value) : def;
}
std::string Properties::get_string(const std::string& name) const { return std::get<std::string>(require(name, Type::String).value); }
std::string Properties::get_string(const std::string& name, const std::string& def) const {
    const Entry* e = find(name, Type::String);
    return e ? std::get<std::string>(e->value) : def;
}
Vec3 Properties::get_point(const std::string& name) const { return std::get<Vec3>(require(name, Type::Point).value); }
Vec3 Properties::get_point(const std::string& name, const Vec3& def) const {
    const Entry* e = find(name, Type::Point);
    return e ? std::get<Vec3>(e->value) : def;
}
Vec3 Properties::get_vector(const std::string& name) const { return std::get<Vec3>(require(name, Type::Vector).value); }
Vec3 Properties::get_vector(const std::string& name, const Vec3& def) const {
    const Entry* e = find(name, Type::Vector);
    return e ? std::get<Vec3>(e->value) : def;
}

static Spectrum as_rgb(const Properties::Value& v) {
    if (auto s = std::get_if<Vec3>(&v)) return *s;
    if (auto o = std::get_if<Ref<Object>>(&v)) return std::static_pointer_cast<ConstantTexture>(*o)->value();
    return Spectrum(float(as_double(v)));
}
// A referenced constant texture stands for its colour; any other object is the usual type error.
static bool is_constant_texture(const Properties::Value& v) {
    auto o = std::get_if<Ref<Object>>(&v);
    return o && std::dynamic_pointer_cast<ConstantTexture>(*o) != nullptr;
}
Spectrum Properties::get_rgb(const std::string& name) const {
    asked_.insert(name);
    auto it = entries_.find(name);
    if (it != entries_.end() && is_constant_texture(it->second.value)) return as_rgb(get_raw(name));
    return as_rgb(require(name, Type::RGB).value);
}
Spectrum Properties::get_rgb(const std::string& name, const Spectrum& def) const {
    asked_.insert(name);
    auto it = entries_.find(name);
    if (it != entries_.end() && is_constant_texture(it->second.value)) return as_rgb(get_raw(name));
    const Entry* e = find(name, Type::RGB);
    return e ? as_rgb(e->value) : def;
}
std::shared_ptr<const SpectrumTexture> Properties::measured_spectrum(const std::string& name) const {
    auto it = entries_.find(name);
    if (it == entries_.end()) return nullptr;
    auto o = std::get_if<Ref<Object>>(&it->second.value);
    return o ? std::dynamic_pointer_cast<const SpectrumTexture>(*o) : nullptr;
}
Transform Properties::get_transform(const std::string& name, const Transform& def) const {
    asked_.insert(name);
    auto it = entries_.find(name);
    if (it != entries_.end() && it->second.type == Type::Animation)
        throw SceneError(it->second.where, "an animated " + name + " (motion blur) is not supported on " + plugin_type_ +
                                               ": only shapes, sensors and point and spot emitters move");
    const Entry* e = find(name, Type::Transform);
    return e ? std::get<Transform>(e->value) : def;
}

AnimatedTransform Properties::get_animated_transform(const std::string& name, const Transform& def) const {
    asked_.insert(name);
    auto it = entries_.find(name);
    if (it != entries_.end() && it->second.type == Type::Animation) {
        it->second.used = true;
        AnimatedTransform animation = std::get<AnimatedTransform>(it->second.value);
        animation.where = it->second.where;
        return animation;
    }
    return AnimatedTransform(get_transform(name, def));
}

std::string Properties::get_path(const std::string& name) const {
    namespace fs = std::filesystem;
    fs::path p(get_string(name));
    SourceLocation where = location_of(name);
    if (p.is_relative() && !where.file.empty()) p = fs::path(where.file).parent_path() / p;
    return p.string();
}

std::string Properties::get_file_path(const std::string& name) const {
    namespace fs = std::filesystem;
    std::string value = get_string(name);
    SourceLocation where = location_of(name);
    FileResolver beside_file;
    if (!resolver_ && !where.file.empty()) beside_file.append(fs::path(where.file).parent_path());
    const FileResolver& resolver = resolver_ ? *resolver_ : beside_file;
    if (auto found = resolver.find_file(value)) return found->string();
    if (fs::path(value).is_absolute()) throw SceneError(where, "file not found: \"" + value + "\"");
    throw SceneError(where, "file not found: \"" + value + "\" (looked in: " + resolver.describe() + ")");
}

Ref<Texture> Properties::get_texture(const std::string& name, const Spectrum& def) const {
    asked_.insert(name);
    auto it = entries_.find(name);
    if (it == entries_.end()) return std::make_shared<ConstantTexture>(def);
    if (it->second.type == Type::Object) {
        auto obj = std::get<Ref<Object>>(it->second.value);
        auto tex = std::dynamic_pointer_cast<Texture>(obj);
        if (!tex)
            throw SceneError(it->second.where,
                             "property \"" + name + "\" of " + plugin_type_ + " must be a texture or rgb, not a " + kind_tag(obj->kind()));
        it->second.used = true;
        return tex;
    }
    return std::make_shared<ConstantTexture>(get_rgb(name));
}

Ref<Texture> Properties::get_reflectance(const std::string& name, const Spectrum& def) const {
    Ref<Texture> texture = get_texture(name, def);
    if (!has(name) || !texture->is_constant()) return texture;
    const Spectrum v = texture->mean();
    char value[96];
    std::snprintf(value, sizeof value, "(%g, %g, %g)", v.x, v.y, v.z);
    if (!all_finite(v) || min_component(v) < 0.0f) fail(name, name + " " + value + " is not a reflectance: it must lie between 0 and 1");
    if (max_component(v) > 1.0f)
        warn(location_of(name),
             name + " " + value + " exceeds 1, which is physically impossible (more light out than in); rendered as given");
    return texture;
}

Ref<Texture> Properties::get_texture(const std::string& name) const {
    if (!has(name)) throw SceneError(location_, plugin_type_ + ": missing required property \"" + name + "\" (texture or rgb)");
    return get_texture(name, Spectrum(0.0f));
}

Ref<Object> Properties::get_object(const std::string& name) const {
    const Entry* e = find(name, Type::Object);
    return e ? std::get<Ref<Object>>(e->value) : nullptr;
}

std::vector<std::pair<std::string, Ref<Object>>> Properties::get_named_objects(ObjectKind kind) const {
    std::vector<std::pair<const std::string*, const Entry*>> found;
    for (auto& [name, e] : entries_) {
        if (e.type != Type::Object) continue;
        if (std::get<Ref<Object>>(e.value)->kind() == kind) found.emplace_back(&name, &e);
    }
    std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.second->order < b.second->order; });
    std::vector<std::pair<std::string, Ref<Object>>> out;
    for (const auto& [name, e] : found) {
        e->used = true;
        out.emplace_back(*name, std::get<Ref<Object>>(e->value));
    }
    return out;
}

std::vector<Ref<Object>> Properties::get_objects(ObjectKind kind) const {
    std::vector<Ref<Object>> out;
    for (auto& named : get_named_objects(kind)) out.push_back(std::move(named.second));
    return out;
}

void Properties::check_all_used() const {
    const Entry* first = nullptr;
    std::string first_name;
    for (auto& [name, e] : entries_)
        if (!e.used && (!first || e.order < first->order)) {
            first = &e;
            first_name = name;
        }
    if (!first) return;
    if (first->type == Type::Object) {
        auto obj = std::get<Ref<Object>>(first->value);
        throw SceneError(first->where, std::string("unexpected nested ") + kind_tag(obj->kind()) + " in " + plugin_type_ +
                                           (first_name.rfind("_arg", 0) == 0 ? "" : " (named \"" + first_name + "\")") +
                                           ": nothing uses it");
    }
    // The nearest name the plugin reads, when it is a plausible misspelling.
    std::vector<std::string> parameters(asked_.begin(), asked_.end());
    const std::string nearest = suggested_name(first_name, parameters);
    throw SceneError(first->where, "unused property \"" + first_name + "\" in " + plugin_type_ + ": no such parameter" +
                                       (nearest.empty() ? "" : "; did you mean \"" + nearest + "\"?"));
}

const Properties::Value& Properties::get_raw(const std::string& name, Type* type) const {
    asked_.insert(name);
    auto it = entries_.find(name);
    if (it == entries_.end()) throw SceneError(location_, plugin_type_ + ": missing property \"" + name + "\"");
    it->second.used = true;
    if (type) *type = it->second.type;
    return it->second.value;
}

std::vector<std::string> Properties::names() const {
    std::vector<std::pair<size_t, std::string>> v;
    for (auto& [name, e] : entries_) v.emplace_back(e.order, name);
    std::sort(v.begin(), v.end());
    std::vector<std::string> out;
    for (auto& p : v) out.push_back(p.second);
    return out;
}

}  // namespace candela
