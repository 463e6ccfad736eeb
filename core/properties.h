#pragma once
// The typed property bag a plugin is built from, as parsed from a scene file. Every read marks
// the property as used; a property that no plugin reads is an error naming its file and line,
// as in Mitsuba 3 (a typo like "reflectence" must not be silently ignored).

#include "core/animated_transform.h"
#include "core/error.h"
#include "core/object.h"
#include "core/spectrum.h"
#include "core/transform.h"
#include "core/variant.h"

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <variant>
#include <vector>

namespace candela {

class Texture;
class SpectrumTexture;
class FileResolver;

class Properties {
public:
    // What a property tag holds. Points and vectors share Vec3; the tag is kept for messages.
    // Points, vectors and rgb values all hold a Vec3 (Spectrum is the same type); `Type` tells them apart.
    using Value = std::variant<int64_t, double, bool, std::string, Vec3, Transform, Ref<Object>, AnimatedTransform>;
    // Animation: an <animation> of keyframed transforms (motion blur).
    enum class Type { Integer, Float, Boolean, String, Point, Vector, RGB, Transform, Object, Animation };

    Properties() = default;
    Properties(std::string plugin_type, SourceLocation where) : plugin_type_(std::move(plugin_type)), location_(std::move(where)) {}

    const std::string& plugin_type() const { return plugin_type_; }
    // The variant the scene is loaded for (the loader sets it on every object's properties):
    // plugins not marked for it are refused (core/registry.h).
    Variant variant() const { return variant_; }
    void set_variant(Variant v) { variant_ = v; }
    const SourceLocation& location() const { return location_; }
    std::string id;

    // Filled by the loader (and by tests). Setting a name twice is an error.
    void set(const std::string& name, Type type, Value value, const SourceLocation& where);
    void set_int(const std::string& name, int64_t v) { set(name, Type::Integer, v, location_); }
    void set_float(const std::string& name, double v) { set(name, Type::Float, v, location_); }
    void set_bool(const std::string& name, bool v) { set(name, Type::Boolean, v, location_); }
    void set_string(const std::string& name, const std::string& v) { set(name, Type::String, v, location_); }
    void set_rgb(const std::string& name, const Spectrum& v) { set(name, Type::RGB, v, location_); }
    void set_transform(const std::string& name, const Transform& v) { set(name, Type::Transform, v, location_); }
    void set_object(const std::string& name, Ref<Object> v, const SourceLocation& where) { set(name, Type::Object, std::move(v), where); }

    bool has(const std::string& name) const {
        asked_.insert(name);
        return entries_.count(name) != 0;
    }

    // Typed reads. Without a default, a missing property is an error. Integers are accepted
    // where floats are asked for, and a single float or a constant texture (a <ref> to a
    // <spectrum type="...">) where an rgb is.
    int get_int(const std::string& name) const;
    int get_int(const std::string& name, int def) const;
    float get_float(const std::string& name) const;
    float get_float(const std::string& name, float def) const;
    bool get_bool(const std::string& name, bool def) const;
    std::string get_string(const std::string& name) const;
    std::string get_string(const std::string& name, const std::string& def) const;
    Vec3 get_point(const std::string& name) const;
    Vec3 get_point(const std::string& name, const Vec3& def) const;
    Vec3 get_vector(const std::string& name) const;
    Vec3 get_vector(const std::string& name, const Vec3& def) const;
    Spectrum get_rgb(const std::string& name) const;
    Spectrum get_rgb(const std::string& name, const Spectrum& def) const;
    // A fixed transform; an <animation> under this name is an error at its line saying that the
    // plugin cannot move (only those that read get_animated_transform can).
    Transform get_transform(const std::string& name, const Transform& def = Transform()) const;
    // A transform that may be animated: an <animation>, or a fixed transform (static).
    AnimatedTransform get_animated_transform(const std::string& name, const Transform& def = Transform()) const;

    // A file name, looked for in the folders of the scene's file resolver (the scene file's own
    // folder, <path> folders, the working directory: see core/file_resolver.h); without a resolver,
    // beside the file that names it. A missing file is an error at the property's line that says
    // where it looked.
    std::string get_file_path(const std::string& name) const;
    // Set by the loader for every object it creates.
    void set_file_resolver(std::shared_ptr<const FileResolver> resolver) { resolver_ = std::move(resolver); }
    const std::shared_ptr<const FileResolver>& file_resolver() const { return resolver_; }
    // A name that need not be one existing file (a pattern of several, such as a cube map's
    // "{face}"), made absolute relative to the file that names it.
    std::string get_path(const std::string& name) const;

    // The measured spectrum an rgb parameter was given as (a <spectrum> of samples, a file, a
    // black body), for the spectral variant; null when it was a colour or is absent.
    std::shared_ptr<const SpectrumTexture> measured_spectrum(const std::string& name) const;
    // A texture-valued parameter: a nested/referenced texture, or an rgb/float constant.
    Ref<Texture> get_texture(const std::string& name, const Spectrum& def) const;
    Ref<Texture> get_texture(const std::string& name) const;  // required
    // A reflectance or transmittance (the fraction of light a surface passes on), read as
    // get_texture. A constant below 0 is an error at its line; one above 1 is accepted with a
    // warning there, as a physically impossible value (more light out than in).
    Ref<Texture> get_reflectance(const std::string& name, const Spectrum& def) const;

    // A named nested object, or null when absent.
    Ref<Object> get_object(const std::string& name) const;
    // All nested objects of a kind, in document order, named or not; each is marked as used.
    std::vector<Ref<Object>> get_objects(ObjectKind kind) const;
    // The same with their names: the name attribute, or "_argN" the loader gives unnamed ones.
    std::vector<std::pair<std::string, Ref<Object>>> get_named_objects(ObjectKind kind) const;

    // Throws a SceneError at the first property (in document order) that nothing read.
    void check_all_used() const;
    // Throws a SceneError at the location of a property (or of the plugin when absent).
    [[noreturn]] void fail(const std::string& name, const std::string& message) const;
    // `value` as an int, or a failure at `name`'s line when it does not fit one.
    int checked_int(const std::string& name, int64_t value) const;
    [[noreturn]] void fail(const std::string& message) const;
    SourceLocation location_of(const std::string& name) const;

    // The stored value and its tag, marked as used (for generic consumers such as dumps).
    const Value& get_raw(const std::string& name, Type* type = nullptr) const;

    // Names in document order (for the loader and for tests).
    std::vector<std::string> names() const;

private:
    Variant variant_ = Variant::ScalarRGB;
    struct Entry {
        Type type;
        Value value;
        SourceLocation where;
        size_t order;
        mutable bool used = false;
    };
    const Entry* find(const std::string& name, Type expected) const;
    const Entry& require(const std::string& name, Type expected) const;

    std::string plugin_type_;
    SourceLocation location_;
    std::map<std::string, Entry> entries_;
    // Every name the plugin asked for, given or not: the parameters it has, for suggesting the
    // nearest to an unused (misspelled) one.
    mutable std::set<std::string> asked_;
    std::shared_ptr<const FileResolver> resolver_;
};

const char* type_name(Properties::Type t);

}  // namespace candela
