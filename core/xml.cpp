#include "core/xml.h"
#include "core/emitter.h"

#include "core/file_resolver.h"
#include "core/registry.h"
#include "core/text.h"
#include "core/texture.h"
#include "core/warning.h"
#include "core/xml_spectrum.h"

#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace candela {

namespace {

const std::map<std::string, ObjectKind>& object_tags() {
    static const std::map<std::string, ObjectKind> tags = {
        {"shape", ObjectKind::Shape},     {"bsdf", ObjectKind::BSDF},       {"emitter", ObjectKind::Emitter},
        {"texture", ObjectKind::Texture}, {"sensor", ObjectKind::Sensor},   {"film", ObjectKind::Film},
        {"rfilter", ObjectKind::Filter},  {"sampler", ObjectKind::Sampler}, {"integrator", ObjectKind::Integrator},
        {"medium", ObjectKind::Medium},   {"phase", ObjectKind::Phase},     {"volume", ObjectKind::Volume},
    };
    return tags;
}

constexpr int MaxIncludeDepth = 15;

struct Document {
    std::string path;
    std::string text;
    std::vector<size_t> line_starts;
    pugi::xml_document xml;
    // Scene files older than version 2.0 (Mitsuba 0.4 to 0.6) are read through Mitsuba 3's
    // upgrade: see property_name(), read_object() and the legacy tags in read_property().
    bool upgrade = false;
    // Where this file's relative file names are looked for; replaced (never changed in place)
    // by each <path>, so objects keep the list that held where they were declared.
    std::shared_ptr<const FileResolver> resolver;
};

// Mitsuba 3's camelCase to snake_case upgrade of a property name (src/core/parser.cpp,
// camel_to_underscore_case): an underscore before each capital that follows a lower-case
// letter, and the run of capitals lower-cased: toWorld -> to_world, intIOR -> int_ior.
std::string camel_to_snake(const std::string& name) {
    std::string out;
    for (size_t i = 0; i < name.size(); ++i) {
        unsigned char c = static_cast<unsigned char>(name[i]);
        if (i > 0 && std::islower(static_cast<unsigned char>(name[i - 1])) && std::isupper(c)) {
            out += '_';
            out += char(std::tolower(c));
            while (i + 1 < name.size() && std::isupper(static_cast<unsigned char>(name[i + 1]))) out += char(std::tolower(name[++i]));
        } else {
            out += char(c);
        }
    }
    return out;
}

// Mitsuba 0.6's <srgb> value, "#rrggbb" or one or three gamma-encoded numbers, made linear.
bool parse_srgb(const std::string& text, const std::vector<double>& numbers, Spectrum& out) {
    if (!text.empty() && text[0] == '#') {
        if (text.size() != 7) return false;
        for (int c = 0; c < 3; ++c) {
            const std::string digits = text.substr(1 + 2 * c, 2);  // outlives `end`, which points into it
            char* end = nullptr;
            long v = std::strtol(digits.c_str(), &end, 16);
            if (*end != '\0') return false;
            out[c] = srgb_to_linear(float(v) / 255.0f);
        }
        return true;
    }
    if (numbers.size() != 1 && numbers.size() != 3) return false;
    for (int c = 0; c < 3; ++c) out[c] = srgb_to_linear(float(numbers[numbers.size() == 1 ? 0 : c]));
    return true;
}

// A shape other than an instance or a group with an <animation> named to_world (motion blur):
// Candela builds it without that transform, puts it alone in a shapegroup and animates an
// instance of the group, so that it moves by Embree's instance motion, as animated instances do.
// The shape's own parameters (a sphere's center and radius, ...) place it inside the group, the
// animation places the group: to_world(t) applied after them, as Mitsuba composes a to_world.
// An area emitter stays on the still shape and learns the instance's motion (Emitter::set_motion).
bool moves_through_instance(ObjectKind kind, const Properties& props) {
    const std::string& type = props.plugin_type();
    if (kind != ObjectKind::Shape || type == "instance" || type == "shapegroup" || !props.has("to_world")) return false;
    Properties::Type tag;
    props.get_raw("to_world", &tag);
    return tag == Properties::Type::Animation;
}

Ref<Object> create_moving_shape(const Properties& props) {
    const SourceLocation& where = props.location();
    Properties still(props.plugin_type(), where), group("shapegroup", where), instance("instance", where);
    still.set_file_resolver(props.file_resolver());
    Properties::Type tag;
    Ref<Emitter> emitter;  // an area light moves with the instance (Emitter::move_with_instance)
    for (const std::string& name : props.names()) {
        if (name == "to_world") continue;
        const Properties::Value& value = props.get_raw(name, &tag);
        if (tag == Properties::Type::Object && std::get<Ref<Object>>(value)->kind() == ObjectKind::Emitter) {
            emitter = std::static_pointer_cast<Emitter>(std::get<Ref<Object>>(value));
            emitter->move_with_instance();
        }
        still.set(name, tag, value, props.location_of(name));
    }
    group.set_object("shape", create_plugin(ObjectKind::Shape, still), where);
    instance.id = props.id;
    const Properties::Value& animation = props.get_raw("to_world", &tag);
    instance.set("to_world", tag, animation, props.location_of("to_world"));
    instance.set_object("group", create_plugin(ObjectKind::Shape, group), where);
    auto moving = std::static_pointer_cast<Shape>(create_plugin(ObjectKind::Shape, instance));
    if (emitter) emitter->set_motion(&moving->motion());
    return moving;
}

class XmlLoader {
public:
    XmlLoader(const SceneParameters& defines, Variant variant, int sensor_index)
        : params_(defines), defines_(defines), variant_(variant), sensor_index_(sensor_index) {}

    // A -D name the scene neither declares (<default>) nor uses ($name) changes nothing: a
    // warning names it and the scene's parameters (Mitsuba ignores it silently).
    void warn_unused_defines(const std::string& path) const {
        std::vector<std::string> known(known_params_.begin(), known_params_.end());
        std::string list;
        for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
        for (const auto& [name, value] : defines_) {
            if (known_params_.count(name)) continue;
            const std::string nearest = suggested_name(name, known);
            warn(SourceLocation{path, 0}, "-D " + name + "=" + value + ": the scene has no parameter \"" + name + "\"" +
                                              (nearest.empty() ? "" : "; did you mean \"" + nearest + "\"?") +
                                              (list.empty() ? " (it declares none)" : " (its parameters: " + list + ")"));
        }
    }

    Ref<Scene> load(const std::string& text, const std::string& path) {
        Document& doc = parse_document(text, path, SourceLocation{path, 0});
        // Mitsuba 3: the scene file's folder, then the working directory, then the folders given
        // with `-a` (FileResolver::set_search_folders); <path>s go in front.
        auto resolver = std::make_shared<FileResolver>();
        resolver->append(fs::absolute(fs::path(path)).parent_path());
        std::error_code ec;
        fs::path cwd = fs::current_path(ec);
        if (!ec) resolver->append(cwd);
        for (const fs::path& folder : FileResolver::search_folders()) resolver->append(folder);
        doc.resolver = resolver;
        pugi::xml_node root = doc.xml.document_element();
        Properties scene_props("scene", where(doc, root));
        scene_props.set_variant(variant_);
        read_scene_element(doc, root, scene_props, 0);
        auto scene = std::make_shared<Scene>(scene_props, sensor_index_);
        scene_props.check_all_used();
        scene->parameters = params_;
        for (const fs::path& f : resolver->found_files())
            if (std::find(scene->input_files.begin(), scene->input_files.end(), f.string()) == scene->input_files.end())
                scene->input_files.push_back(f.string());
        return scene;
    }

private:
    Document& parse_document(const std::string& text, const std::string& path, const SourceLocation& included_from) {
        auto doc = std::make_unique<Document>();
        doc->path = path;
        doc->text = text;
        doc->line_starts.push_back(0);
        for (size_t i = 0; i < text.size(); ++i)
            if (text[i] == '\n') doc->line_starts.push_back(i + 1);
        pugi::xml_parse_result result = doc->xml.load_buffer(doc->text.data(), doc->text.size(), pugi::parse_default, pugi::encoding_utf8);
        if (!result)
            throw SceneError(SourceLocation{path, line_of(*doc, size_t(result.offset))},
                             std::string("malformed XML: ") + result.description());
        pugi::xml_node root = doc->xml.document_element();
        if (!root) throw SceneError(SourceLocation{path, 1}, "malformed XML: no root element");
        docs_.push_back(std::move(doc));
        return *docs_.back();
    }

    static int line_of(const Document& doc, size_t offset) {
        auto it = std::upper_bound(doc.line_starts.begin(), doc.line_starts.end(), offset);
        return int(it - doc.line_starts.begin());
    }
    static SourceLocation where(const Document& doc, const pugi::xml_node& node) {
        return SourceLocation{doc.path, line_of(doc, size_t(node.offset_debug()))};
    }

    // Replaces $name with the parameter's value; an undefined parameter is an error.
    std::string substitute(const Document& doc, const pugi::xml_node& node, const std::string& value) const {
        if (value.find('$') == std::string::npos) return value;
        std::string out;
        for (size_t i = 0; i < value.size();) {
            if (value[i] != '$') {
                out += value[i++];
                continue;
            }
            size_t j = i + 1;
            while (j < value.size() && (std::isalnum(static_cast<unsigned char>(value[j])) || value[j] == '_')) ++j;
            std::string name = value.substr(i + 1, j - i - 1);
            if (name.empty()) throw SceneError(where(doc, node), "stray '$' in \"" + value + "\"");
            auto it = params_.find(name);
            if (it == params_.end())
                throw SceneError(where(doc, node), "undefined parameter $" + name + " (define it with <default> or -D " + name + "=...)");
            known_params_.insert(name);
            out += it->second;
            i = j;
        }
        return out;
    }

    void check_attributes(const Document& doc, const pugi::xml_node& node, std::initializer_list<const char*> allowed) const {
        for (pugi::xml_attribute a : node.attributes()) {
            bool ok = false;
            for (const char* name : allowed) ok = ok || std::strcmp(a.name(), name) == 0;
            if (!ok) throw SceneError(where(doc, node), std::string("unexpected attribute \"") + a.name() + "\" in <" + node.name() + ">");
        }
    }

    bool has_attr(const pugi::xml_node& node, const char* name) const { return bool(node.attribute(name)); }

    std::string attr(const Document& doc, const pugi::xml_node& node, const char* name) const {
        pugi::xml_attribute a = node.attribute(name);
        if (!a) throw SceneError(where(doc, node), std::string("<") + node.name() + "> needs the attribute \"" + name + "\"");
        return substitute(doc, node, a.value());
    }
    std::string attr_or(const Document& doc, const pugi::xml_node& node, const char* name, const std::string& def) const {
        pugi::xml_attribute a = node.attribute(name);
        return a ? substitute(doc, node, a.value()) : def;
    }

    // --- numbers ---------------------------------------------------------------------------

    static std::string trim(const std::string& s) {
        size_t b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
        return b == std::string::npos ? "" : s.substr(b, e - b + 1);
    }

    double parse_double(const Document& doc, const pugi::xml_node& node, const std::string& text) const {
        std::string t = trim(text);
        char* end = nullptr;
        double v = std::strtod(t.c_str(), &end);
        if (t.empty() || end != t.c_str() + t.size()) throw SceneError(where(doc, node), "\"" + text + "\" is not a number");
        if (!std::isfinite(v)) throw SceneError(where(doc, node), "\"" + text + "\" is not a finite number");
        // Every number a plugin reads becomes a float: beyond its range it would be infinite.
        if (std::fabs(v) > double(std::numeric_limits<float>::max()))
            throw SceneError(where(doc, node), "\"" + text + "\" is beyond the range of a 32-bit float (magnitude at most 3.4e38)");
        return v;
    }

    std::vector<double> parse_list(const Document& doc, const pugi::xml_node& node, const std::string& text) const {
        std::vector<double> out;
        for (const std::string& item : split_list(text)) out.push_back(parse_double(doc, node, item));
        return out;
    }

    // "x, y, z" (or one value, repeated) from `value`, or separate x/y/z attributes with a default.
    Vec3 parse_vec3(const Document& doc, const pugi::xml_node& node, float def) const {
        if (has_attr(node, "value")) {
            if (has_attr(node, "x") || has_attr(node, "y") || has_attr(node, "z"))
                throw SceneError(where(doc, node), std::string("<") + node.name() + "> takes either value or x/y/z, not both");
            auto v = parse_list(doc, node, attr(doc, node, "value"));
            if (v.size() == 1) return Vec3(float(v[0]));
            if (v.size() != 3) throw SceneError(where(doc, node), std::string("<") + node.name() + "> value needs 1 or 3 numbers");
            return Vec3(float(v[0]), float(v[1]), float(v[2]));
        }
        Vec3 r(def);
        const char* names[3] = {"x", "y", "z"};
        for (int i = 0; i < 3; ++i)
            if (has_attr(node, names[i])) r[i] = float(parse_double(doc, node, attr(doc, node, names[i])));
        return r;
    }

    Vec3 parse_point_attr(const Document& doc, const pugi::xml_node& node, const char* name) const {
        auto v = parse_list(doc, node, attr(doc, node, name));
        if (v.size() != 3) throw SceneError(where(doc, node), std::string("\"") + name + "\" needs 3 numbers");
        return Vec3(float(v[0]), float(v[1]), float(v[2]));
    }

    // --- scene, objects, properties ----------------------------------------------------------

    void read_scene_element(Document& doc, const pugi::xml_node& root, Properties& scene_props, int depth) {
        if (std::strcmp(root.name(), "scene") != 0)
            throw SceneError(where(doc, root), std::string("the root element must be <scene>, not <") + root.name() + ">");
        check_attributes(doc, root, {"version"});
        std::string version = attr(doc, root, "version");
        int major = 0, minor = 0, patch = 0;
        if (std::sscanf(version.c_str(), "%d.%d.%d", &major, &minor, &patch) != 3)
            throw SceneError(where(doc, root), "version \"" + version + "\" is not of the form major.minor.patch");
        doc.upgrade = major < 2;
        scan_declarations(doc, root);
        for (pugi::xml_node child : root.children()) read_child(doc, child, scene_props, /*in_scene=*/true, depth);
    }

    void read_child(Document& doc, const pugi::xml_node& child, Properties& props, bool in_scene, int depth) {
        if (child.type() == pugi::node_pcdata || child.type() == pugi::node_cdata) {
            if (!trim(child.value()).empty()) throw SceneError(where(doc, child), "unexpected text \"" + trim(child.value()) + "\"");
            return;
        }
        if (child.type() != pugi::node_element) return;
        std::string tag = child.name();
        auto kind = object_tags().find(tag);
        if (kind != object_tags().end() && kind->second == ObjectKind::Shape && attr_or(doc, child, "type", "") == "merge") {
            read_merge(doc, child, props, in_scene);
        } else if (kind != object_tags().end()) {
            Ref<Object> obj = read_object(doc, child, kind->second);
            std::string name = has_attr(child, "name") ? property_name(doc, child) : next_arg_name();
            props.set_object(name, obj, where(doc, child));
        } else if (tag == "spectrum" && has_attr(child, "type")) {
            read_spectrum_plugin(doc, child, props);
        } else if (tag == "ref") {
            check_attributes(doc, child, {"id", "name"});
            std::string id = attr(doc, child, "id");
            Ref<Object> target = find_id(doc, child, id);
            std::string name = has_attr(child, "name") ? property_name(doc, child) : next_arg_name();
            props.set_object(name, target, where(doc, child));
        } else if (tag == "default") {
            if (!in_scene) throw SceneError(where(doc, child), "<default> may only appear directly inside <scene>");
            check_attributes(doc, child, {"name", "value"});
            std::string name = child.attribute("name").value();
            if (!child.attribute("name") || !child.attribute("value"))
                throw SceneError(where(doc, child), "<default> needs name and value");
            if (!params_.count(name)) params_[name] = substitute(doc, child, child.attribute("value").value());
            known_params_.insert(name);
        } else if (tag == "include") {
            if (!in_scene) throw SceneError(where(doc, child), "<include> may only appear directly inside <scene>");
            check_attributes(doc, child, {"filename"});
            include(doc, child, props, depth);
        } else if (tag == "path") {
            if (!in_scene) throw SceneError(where(doc, child), "<path> may only appear directly inside <scene>");
            add_search_path(doc, child);
        } else if (tag == "alias") {
            check_attributes(doc, child, {"id", "as"});
            std::string id = attr(doc, child, "id"), as = attr(doc, child, "as");
            if (!ids_.count(id) && !declared_.count(id)) throw SceneError(where(doc, child), "<alias> of unknown id \"" + id + "\"");
            if (ids_.count(as)) throw SceneError(where(doc, child), "duplicate id \"" + as + "\"");
            ids_[as] = find_id(doc, child, id);
        } else if (tag == "animation") {
            check_attributes(doc, child, {"name"});
            props.set(property_name(doc, child), Properties::Type::Animation, read_animation(doc, child), where(doc, child));
        } else if (tag == "resource_path") {
            throw SceneError(where(doc, child), "unknown element <resource_path> (Mitsuba 3 calls it <path value=\"...\"/>)");
        } else {
            read_property(doc, child, props);
        }
    }

    // <shape type="merge">: Mitsuba 3's merge shape joins the meshes it holds that share a BSDF,
    // media, emitter and sensor into one mesh, to save memory and BVH work, and passes its other
    // shapes through; no pixel changes. Candela takes every shape it holds (nested merges too) as
    // the scene's own, written in its place. It holds shapes only and sits directly in <scene>;
    // its id names nothing.
    void read_merge(Document& doc, const pugi::xml_node& node, Properties& scene_props, bool in_scene) {
        check_attributes(doc, node, {"type", "id", "name"});
        if (!in_scene) throw SceneError(where(doc, node), "a merge shape must be directly inside <scene>");
        for (pugi::xml_node child : node.children()) {
            const bool shape = child.type() != pugi::node_element || std::strcmp(child.name(), "shape") == 0;
            if (!shape) throw SceneError(where(doc, child), std::string("a merge shape holds shapes only, not <") + child.name() + ">");
            read_child(doc, child, scene_props, /*in_scene=*/true, 0);
        }
    }

    // The name attribute of a property or nested object. In a pre-2.0 scene it is upgraded as
    // Mitsuba 3 does: camelCase to snake_case, and a diffuse BSDF's diffuse_reflectance is its
    // reflectance.
    std::string property_name(const Document& doc, const pugi::xml_node& node) const {
        std::string name = attr(doc, node, "name");
        if (!doc.upgrade) return name;
        name = camel_to_snake(name);
        pugi::xml_node parent = node.parent();
        if (name == "diffuse_reflectance" && std::strcmp(parent.name(), "bsdf") == 0 && attr_or(doc, parent, "type", "") == "diffuse")
            return "reflectance";
        return name;
    }

    // <path value="folder"/>: the folder, found like any file name (relative to this file's folder
    // first), goes in front of the search list for everything after it in this file and in the
    // files it includes (Mitsuba 3's FileResolver::prepend).
    void add_search_path(Document& doc, const pugi::xml_node& node) {
        check_attributes(doc, node, {"value"});
        std::string value = attr(doc, node, "value");
        auto found = doc.resolver->find_directory(value);
        if (!found)
            throw SceneError(where(doc, node), "<path>: folder \"" + value + "\" not found (looked in: " + doc.resolver->describe() + ")");
        auto resolver = std::make_shared<FileResolver>(*doc.resolver);
        resolver->prepend(fs::absolute(*found).lexically_normal());
        doc.resolver = resolver;
    }

    std::string next_arg_name() { return "_arg" + std::to_string(arg_counter_++); }

    void include(Document& doc, const pugi::xml_node& node, Properties& scene_props, int depth) {
        if (depth + 1 > MaxIncludeDepth) throw SceneError(where(doc, node), "includes nest too deeply (a cycle?)");
        std::string name = attr(doc, node, "filename");
        auto found = doc.resolver->find_file(name);
        std::ifstream in;
        if (found) in.open(*found, std::ios::binary);
        if (!found || !in)
            throw SceneError(where(doc, node), "cannot open included file \"" + name + "\" (looked in: " + doc.resolver->describe() + ")");
        std::stringstream ss;
        ss << in.rdbuf();
        Document& inc = parse_document(ss.str(), found->string(), where(doc, node));
        // The included file's own folder first, then everything the including file searches.
        auto resolver = std::make_shared<FileResolver>(*doc.resolver);
        resolver->prepend(fs::absolute(*found).parent_path());
        inc.resolver = resolver;
        read_scene_element(inc, inc.xml.document_element(), scene_props, depth + 1);
    }

    // The object an id names. Mitsuba resolves references after reading the whole file, so an
    // object may be declared after the <ref> that uses it: such a declaration (found by the scan
    // in read_scene_element) is built on first use and reused when the reading gets to it.
    Ref<Object> find_id(Document& doc, const pugi::xml_node& ref, const std::string& id) {
        auto it = ids_.find(id);
        if (it != ids_.end()) return it->second;
        auto later = declared_.find(id);
        if (later == declared_.end()) throw SceneError(where(doc, ref), "reference to unknown id \"" + id + "\"");
        auto& [decl_doc, decl_node] = later->second;
        if (building_.count(decl_node.internal_object())) throw SceneError(where(doc, ref), "circular reference to id \"" + id + "\"");
        return read_object(*decl_doc, decl_node, object_tags().at(decl_node.name()));
    }

    // Remembers every object with an id in this file, for references that come before it.
    void scan_declarations(Document& doc, const pugi::xml_node& node) {
        for (pugi::xml_node child : node.children()) {
            if (child.type() != pugi::node_element) continue;
            if (object_tags().count(child.name()) && has_attr(child, "id")) {
                std::string id = attr_or(doc, child, "id", "");
                if (!declared_.count(id)) declared_[id] = {&doc, child};
            }
            scan_declarations(doc, child);
        }
    }

    Ref<Object> read_object(Document& doc, const pugi::xml_node& node, ObjectKind kind) {
        auto built = built_.find(node.internal_object());
        if (built != built_.end()) return built->second;
        building_.insert(node.internal_object());
        check_attributes(doc, node, {"type", "id", "name"});
        std::string type = attr(doc, node, "type");
        Properties props(type, where(doc, node));
        props.set_variant(variant_);
        std::string id = attr_or(doc, node, "id", "");
        props.id = id;
        if (!id.empty() && ids_.count(id)) throw SceneError(where(doc, node), "duplicate id \"" + id + "\"");
        props.set_file_resolver(doc.resolver);
        read_children(doc, node, props);
        Ref<Object> obj = moves_through_instance(kind, props) ? create_moving_shape(props) : create_plugin(kind, props);
        if (!id.empty()) ids_[id] = obj;
        building_.erase(node.internal_object());
        built_[node.internal_object()] = obj;
        return obj;
    }

    // An object's children. In a pre-2.0 scene the floats uoffset, voffset, uscale and vscale
    // become the transform to_uv = scale(uscale, vscale) * translate(uoffset, voffset), as in
    // Mitsuba 3's upgrade.
    void read_children(Document& doc, const pugi::xml_node& node, Properties& props) {
        Vec3 offset(0.0f), scale(1.0f);
        SourceLocation uv_location;
        for (pugi::xml_node child : node.children()) {
            if (doc.upgrade && std::strcmp(child.name(), "float") == 0 && has_attr(child, "name")) {
                std::string name = property_name(doc, child);
                int axis = (name == "uoffset" || name == "uscale") ? 0 : (name == "voffset" || name == "vscale") ? 1 : -1;
                if (axis >= 0) {
                    check_attributes(doc, child, {"name", "value"});
                    float v = float(parse_double(doc, child, attr(doc, child, "value")));
                    (name[1] == 'o' ? offset : scale)[axis] = v;
                    if (uv_location.file.empty()) uv_location = where(doc, child);
                    continue;
                }
            }
            read_child(doc, child, props, false, 0);
        }
        if (!uv_location.file.empty())
            props.set("to_uv", Properties::Type::Transform, Transform::scale(scale) * Transform::translate(offset), uv_location);
    }

    // <spectrum type="..." [name] [id]>: a constant colour (see core/xml_spectrum.cpp). Named, it
    // is a property of the enclosing object; with an id (or at the top level) it is a constant
    // texture that <ref> can name.
    void read_spectrum_plugin(Document& doc, const pugi::xml_node& node, Properties& parent) {
        check_attributes(doc, node, {"type", "id", "name"});
        SourceLocation loc = where(doc, node);
        Properties props(attr(doc, node, "type"), loc);
        props.set_variant(variant_);
        props.set_file_resolver(doc.resolver);
        read_children(doc, node, props);
        std::string name = has_attr(node, "name") ? property_name(doc, node) : "";
        SpectrumRole role = spectrum_role(node.parent().name(), name);
        Ref<Object> texture;
        SampledSpectrum measured;
        Spectrum rgb = spectrum_plugin_rgb(props, role, &texture, &measured);
        props.check_all_used();
        // The spectral variant uses a measured spectrum per wavelength, not through its colour.
        if (!texture && variant_ != Variant::ScalarRGB && !measured.wavelengths.empty())
            texture = std::make_shared<SpectrumTexture>(rgb, std::move(measured));
        if (!texture) texture = std::make_shared<ConstantTexture>(rgb);
        std::string id = attr_or(doc, node, "id", "");
        if (!id.empty()) {
            if (ids_.count(id)) throw SceneError(loc, "duplicate id \"" + id + "\"");
            texture->id = id;
            ids_[id] = texture;
        }
        if (name.empty())
            parent.set_object(next_arg_name(), texture, loc);
        else if (std::dynamic_pointer_cast<ConstantTexture>(texture) && !std::dynamic_pointer_cast<SpectrumTexture>(texture))
            parent.set(name, Properties::Type::RGB, rgb, loc);
        else
            parent.set_object(name, texture, loc);
    }

    void read_property(Document& doc, const pugi::xml_node& node, Properties& props) {
        std::string tag = node.name();
        SourceLocation loc = where(doc, node);
        if (tag == "transform") {
            check_attributes(doc, node, {"name"});
            props.set(property_name(doc, node), Properties::Type::Transform, read_transform(doc, node), loc);
            return;
        }
        for (pugi::xml_node c : node.children())
            if (c.type() == pugi::node_element) throw SceneError(where(doc, c), "<" + tag + "> cannot contain <" + c.name() + ">");
        if (tag == "translate" || tag == "rotate" || tag == "scale" || tag == "matrix" || tag == "lookat" ||
            (doc.upgrade && tag == "lookAt")) {
            throw SceneError(loc, "<" + tag + "> must be inside a <transform>");
        } else if (tag == "rgb" || tag == "spectrum" || tag == "srgb" || tag == "blackbody") {
            read_colour(doc, node, props);
        } else {
            read_scalar_property(doc, node, props);
        }
    }

    void read_scalar_property(Document& doc, const pugi::xml_node& node, Properties& props) {
        std::string tag = node.name();
        SourceLocation loc = where(doc, node);
        if (tag == "integer") {
            check_attributes(doc, node, {"name", "value"});
            std::string v = trim(attr(doc, node, "value"));
            long long i = 0;
            bool too_large = false;
            if (!parse_integer(v, i, &too_large))
                throw SceneError(loc, "\"" + v + "\" is " + (too_large ? "too large for an integer" : "not an integer"));
            props.set(property_name(doc, node), Properties::Type::Integer, int64_t(i), loc);
        } else if (tag == "float") {
            check_attributes(doc, node, {"name", "value"});
            props.set(property_name(doc, node), Properties::Type::Float, parse_double(doc, node, attr(doc, node, "value")), loc);
        } else if (tag == "boolean") {
            check_attributes(doc, node, {"name", "value"});
            std::string v = to_lower(trim(attr(doc, node, "value")));
            if (v != "true" && v != "false") throw SceneError(loc, "\"" + v + "\" is not a boolean (true or false)");
            props.set(property_name(doc, node), Properties::Type::Boolean, v == "true", loc);
        } else if (tag == "string") {
            check_attributes(doc, node, {"name", "value"});
            props.set(property_name(doc, node), Properties::Type::String, attr(doc, node, "value"), loc);
        } else if (tag == "point" || tag == "vector") {
            check_attributes(doc, node, {"name", "value", "x", "y", "z"});
            props.set(property_name(doc, node), tag == "point" ? Properties::Type::Point : Properties::Type::Vector,
                      parse_vec3(doc, node, 0.0f), loc);
        } else {
            throw SceneError(loc, "unknown element <" + tag + ">");
        }
    }

    // <rgb>, <spectrum> (one value, wavelength:value pairs, or a .spd file), and in pre-2.0
    // scenes Mitsuba 0.6's <srgb> and <blackbody> and the intent attribute. Spectra become colours
    // as in Mitsuba 3's RGB variants: see core/xml_spectrum.h for reflectance versus emission.
    void read_colour(Document& doc, const pugi::xml_node& node, Properties& props) {
        std::string tag = node.name();
        SourceLocation loc = where(doc, node);
        if (tag == "rgb")
            check_attributes(doc, node, {"name", "value", "intent"});
        else if (tag == "spectrum")
            check_attributes(doc, node, {"name", "value", "filename", "intent"});
        else if (tag == "srgb")
            check_attributes(doc, node, {"name", "value", "intent"});
        else
            check_attributes(doc, node, {"name", "temperature", "scale"});
        if (!doc.upgrade && (tag == "srgb" || tag == "blackbody" || has_attr(node, "intent")))
            throw SceneError(loc, (has_attr(node, "intent") && tag != "srgb" && tag != "blackbody" ? std::string("the intent attribute")
                                                                                                   : "<" + tag + ">") +
                                      " is Mitsuba 0.6 syntax, read only in scenes of version below 2.0 (write " +
                                      (tag == "blackbody" ? "<spectrum type=\"blackbody\">" : "<rgb> with linear values") + ")");
        std::string name = property_name(doc, node);
        SpectrumRole role = spectrum_role(node.parent().name(), name);
        std::string intent = attr_or(doc, node, "intent", "");
        if (intent == "illuminant")
            role = SpectrumRole::Emission;
        else if (intent == "reflectance")
            role = role == SpectrumRole::Emission ? SpectrumRole::Reflectance : role;
        else if (!intent.empty())
            throw SceneError(loc, "intent must be reflectance or illuminant, not \"" + intent + "\"");
        SampledSpectrum measured;
        Spectrum rgb = colour_value(doc, node, role, &measured);
        // The spectral variant uses a measured spectrum per wavelength, not through its colour.
        if (variant_ != Variant::ScalarRGB && !measured.wavelengths.empty())
            props.set_object(name, std::make_shared<SpectrumTexture>(rgb, std::move(measured)), loc);
        else
            props.set(name, Properties::Type::RGB, rgb, loc);
    }

    // The colour of a colour element; `measured` receives the spectrum behind it when there is one
    // (samples, a file, a black body, an equal-energy emission).
    Spectrum colour_value(Document& doc, const pugi::xml_node& node, SpectrumRole role, SampledSpectrum* measured) {
        std::string tag = node.name();
        SourceLocation loc = where(doc, node);
        if (tag == "blackbody") {
            // Mitsuba 0.6: temperature="5000K", scale multiplies (W m^-2 sr^-1 nm^-1).
            std::string t = trim(attr(doc, node, "temperature"));
            if (!t.empty() && (t.back() == 'K' || t.back() == 'k')) t.pop_back();
            double temperature = parse_double(doc, node, t), scale = parse_double(doc, node, attr_or(doc, node, "scale", "1"));
            if (!(temperature > 0.0)) throw SceneError(loc, "the temperature must be positive (in kelvin)");
            *measured = blackbody_samples(temperature, CieMin, CieMax, scale);
            return blackbody_rgb(temperature) * float(scale);
        }
        if (tag == "spectrum" && has_attr(node, "filename") == has_attr(node, "value"))
            throw SceneError(loc, "<spectrum> takes either value or filename");
        if (tag == "spectrum" && has_attr(node, "filename")) return spectrum_from_file(doc, node, role, measured);
        std::string text = attr(doc, node, "value");
        if (tag == "spectrum" && text.find(':') != std::string::npos) {
            try {
                *measured = parse_spectrum_pairs(text);
                return sampled_spectrum_rgb(*measured, role, loc);
            } catch (const SpectrumFormatError& e) {
                throw SceneError(loc, std::string("<spectrum>: ") + e.what());
            }
        }
        std::vector<double> v = tag == "srgb" && trim(text).rfind('#', 0) == 0 ? std::vector<double>() : parse_list(doc, node, text);
        Spectrum rgb;
        if (tag == "srgb") {
            if (!parse_srgb(trim(text), v, rgb)) throw SceneError(loc, "<srgb> value needs \"#rrggbb\" or 1 or 3 numbers");
        } else if (v.size() == 1) {
            rgb = tag == "rgb" ? Spectrum(float(v[0])) : uniform_spectrum_rgb(v[0], role);
            // An emitter's single value is an equal-energy spectrum, not the emission of a grey.
            // So is a film's (a flat sensor response over the visible range).
            if (tag != "rgb" && (role == SpectrumRole::Emission || role == SpectrumRole::Response))
                *measured = SampledSpectrum{{CieMin, CieMax}, {v[0], v[0]}};
        } else if (v.size() == 3 && (tag == "rgb" || doc.upgrade)) {
            // <rgb>, or a pre-2.0 <spectrum> of three bins: Mitsuba 0.6's RGB builds read it as rgb.
            rgb = Spectrum(float(v[0]), float(v[1]), float(v[2]));
        } else if (tag == "rgb") {
            throw SceneError(loc, "<rgb> value needs 1 or 3 numbers");
        } else {
            throw SceneError(loc, "<spectrum> value needs one number or wavelength:value pairs such as \"400:0.2, 700:0.8\"");
        }
        return rgb;
    }

    // <spectrum filename="x.spd"/>: found through the file resolver, one "wavelength value" pair
    // per line with '#' comments.
    Spectrum spectrum_from_file(Document& doc, const pugi::xml_node& node, SpectrumRole role, SampledSpectrum* measured) {
        SourceLocation loc = where(doc, node);
        std::string name = attr(doc, node, "filename");
        auto found = doc.resolver->find_file(name);
        if (!found) throw SceneError(loc, "file not found: \"" + name + "\" (looked in: " + doc.resolver->describe() + ")");
        std::ifstream in(*found, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        if (!in) throw SceneError(loc, "cannot read spectrum file \"" + found->string() + "\"");
        try {
            *measured = parse_spd(ss.str());
            return sampled_spectrum_rgb(*measured, role, loc);
        } catch (const SpectrumFormatError& e) {
            throw SceneError(loc, "spectrum file \"" + found->string() + "\": " + e.what());
        }
    }

    // Mitsuba 3's <animation name="..."> of <transform time="..."> keyframes, times increasing.
    AnimatedTransform read_animation(Document& doc, const pugi::xml_node& node) {
        std::vector<std::pair<float, Transform>> keyframes;
        for (pugi::xml_node key : node.children()) {
            if (key.type() != pugi::node_element) continue;
            SourceLocation loc = where(doc, key);
            if (std::strcmp(key.name(), "transform") != 0)
                throw SceneError(loc, "<animation> holds <transform time=\"...\"> keyframes, not <" + std::string(key.name()) + ">");
            check_attributes(doc, key, {"time"});
            double time = parse_double(doc, key, attr(doc, key, "time"));
            if (!std::isfinite(time)) throw SceneError(loc, "a keyframe's time must be finite");
            if (!keyframes.empty() && !(float(time) > keyframes.back().first))
                throw SceneError(loc, "keyframe times must increase (this one is not after the previous one)");
            keyframes.emplace_back(float(time), read_transform(doc, key));
        }
        if (keyframes.empty()) throw SceneError(where(doc, node), "<animation> needs at least one <transform time=\"...\"> keyframe");
        return AnimatedTransform(keyframes);
    }

    Transform read_transform(Document& doc, const pugi::xml_node& node) {
        Transform t;
        for (pugi::xml_node op : node.children()) {
            if (op.type() != pugi::node_element) continue;
            std::string tag = op.name();
            SourceLocation loc = where(doc, op);
            Transform m;
            if (tag == "translate") {
                check_attributes(doc, op, {"x", "y", "z", "value"});
                m = Transform::translate(parse_vec3(doc, op, 0.0f));
            } else if (tag == "scale") {
                check_attributes(doc, op, {"x", "y", "z", "value"});
                m = Transform::scale(parse_vec3(doc, op, 1.0f));
            } else if (tag == "rotate") {
                check_attributes(doc, op, {"x", "y", "z", "value", "angle"});
                Vec3 axis = parse_vec3(doc, op, 0.0f);
                if (squared_length(axis) == 0.0f) throw SceneError(loc, "<rotate> needs a non-zero axis");
                m = Transform::rotate(axis, float(parse_double(doc, op, attr(doc, op, "angle"))));
            } else if (tag == "matrix") {
                check_attributes(doc, op, {"value"});
                auto v = parse_list(doc, op, attr(doc, op, "value"));
                Mat4 mat(1.0f);
                if (v.size() == 16) {
                    for (int r = 0; r < 4; ++r)
                        for (int c = 0; c < 4; ++c) mat[c][r] = float(v[size_t(r) * 4 + c]);
                } else if (v.size() == 9) {
                    for (int r = 0; r < 3; ++r)
                        for (int c = 0; c < 3; ++c) mat[c][r] = float(v[size_t(r) * 3 + c]);
                } else {
                    throw SceneError(loc, "<matrix> needs 16 (4x4) or 9 (3x3) numbers, got " + std::to_string(v.size()));
                }
                m = Transform(mat);
            } else if (tag == "lookat" || (doc.upgrade && tag == "lookAt")) {
                check_attributes(doc, op, {"origin", "target", "up"});
                Vec3 origin = parse_point_attr(doc, op, "origin"), target = parse_point_attr(doc, op, "target");
                Vec3 up = has_attr(op, "up") ? parse_point_attr(doc, op, "up") : Vec3(0.0f);
                if (origin == target) throw SceneError(loc, "<lookat> origin and target coincide");
                m = Transform::look_at(origin, target, up);
                if (!m.all_finite()) throw SceneError(loc, "invalid lookat (is up parallel to the view direction?)");
            } else {
                throw SceneError(loc, "unknown transform operation <" + tag + ">");
            }
            if (!m.all_finite()) throw SceneError(loc, "<" + tag + "> gives a singular or non-finite transform");
            t = m * t;  // later operations apply after earlier ones
            if (!t.all_finite()) throw SceneError(loc, "transform becomes singular or non-finite here");
        }
        return t;
    }

    std::vector<std::unique_ptr<Document>> docs_;
    SceneParameters params_;
    SceneParameters defines_;  // as given (-D)
    Variant variant_;
    int sensor_index_;
    mutable std::set<std::string> known_params_;  // declared by <default> or used as $name
    std::map<std::string, Ref<Object>> ids_;
    std::map<std::string, std::pair<Document*, pugi::xml_node>> declared_;  // ids declared anywhere in the files read
    std::map<const void*, Ref<Object>> built_;                              // object elements built so far
    std::set<const void*> building_;                                        // object elements being built
    int arg_counter_ = 0;
};

}  // namespace

namespace {

// Why `path` cannot be a scene file, when that is clear before parsing it: it is missing, a
// folder, unreadable, or an image (what a newcomer passes after a first render); "" otherwise.
std::string not_a_scene_file(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return "no such file";
    if (fs::is_directory(path, ec)) return "is a directory, not a scene file (give the .xml file in it)";
    std::ifstream in(path, std::ios::binary);
    if (!in) return "cannot read it (permission denied?)";
    unsigned char head[8] = {0};
    in.read(reinterpret_cast<char*>(head), sizeof head);
    const auto starts = [&](std::initializer_list<unsigned char> magic) { return std::equal(magic.begin(), magic.end(), head); };
    if (starts({0x76, 0x2f, 0x31, 0x01}))
        return "this is an OpenEXR image, not a scene file (give the .xml scene; `candela compare` compares images)";
    if (starts({0x89, 'P', 'N', 'G'})) return "this is a PNG image, not a scene file (give the .xml scene)";
    if (starts({0xff, 0xd8, 0xff})) return "this is a JPEG image, not a scene file (give the .xml scene)";
    return "";
}

}  // namespace

Ref<Scene> load_scene(const std::string& path, const SceneParameters& defines, Variant variant, int sensor_index) {
    if (std::string reason = not_a_scene_file(path); !reason.empty()) throw SceneError(SourceLocation{path, 0}, reason);
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    XmlLoader loader(defines, variant, sensor_index);
    auto scene = loader.load(ss.str(), path);
    loader.warn_unused_defines(path);
    return scene;
}

Ref<Scene> load_scene_from_string(const std::string& xml, const std::string& virtual_path, const SceneParameters& defines, Variant variant,
                                  int sensor_index) {
    XmlLoader loader(defines, variant, sensor_index);
    auto scene = loader.load(xml, virtual_path);
    loader.warn_unused_defines(virtual_path);
    return scene;
}

}  // namespace candela
