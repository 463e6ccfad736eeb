#include "core/xml.h"

#include "core/registry.h"

#include <pugixml.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
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
    };
    return tags;
}

constexpr int MaxIncludeDepth = 15;

struct Document {
    std::string path;
    std::string text;
    std::vector<size_t> line_starts;
    pugi::xml_document xml;
};

class XmlLoader {
public:
    explicit XmlLoader(const SceneParameters& defines) : params_(defines) {}

    Ref<Scene> load(const std::string& text, const std::string& path) {
        Document& doc = parse_document(text, path, SourceLocation{path, 0});
        pugi::xml_node root = doc.xml.document_element();
        Properties scene_props("scene", where(doc, root));
        read_scene_element(doc, root, scene_props, 0);
        auto scene = std::make_shared<Scene>(scene_props);
        scene_props.check_all_used();
        scene->parameters = params_;
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
        if (!result) throw SceneError(SourceLocation{path, line_of(*doc, size_t(result.offset))},
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
        if (t.empty() || end != t.c_str() + t.size())
            throw SceneError(where(doc, node), "\"" + text + "\" is not a number");
        if (!std::isfinite(v)) throw SceneError(where(doc, node), "\"" + text + "\" is not a finite number");
        return v;
    }

    std::vector<double> parse_list(const Document& doc, const pugi::xml_node& node, const std::string& text) const {
        std::vector<double> out;
        std::string token;
        auto flush = [&] {
            if (!token.empty()) out.push_back(parse_double(doc, node, token));
            token.clear();
        };
        for (char c : text) {
            if (c == ',' || std::isspace(static_cast<unsigned char>(c))) flush();
            else token += c;
        }
        flush();
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
        if (major < 2)
            throw SceneError(where(doc, root), "scene version " + version + " predates Mitsuba 2; only version 2 and 3 scenes are read");
        for (pugi::xml_node child : root.children()) read_child(doc, child, scene_props, /*in_scene=*/true, depth);
    }

    void read_child(Document& doc, const pugi::xml_node& child, Properties& props, bool in_scene, int depth) {
        if (child.type() == pugi::node_pcdata || child.type() == pugi::node_cdata) {
            if (!trim(child.value()).empty())
                throw SceneError(where(doc, child), "unexpected text \"" + trim(child.value()) + "\"");
            return;
        }
        if (child.type() != pugi::node_element) return;
        std::string tag = child.name();
        auto kind = object_tags().find(tag);
        if (kind != object_tags().end()) {
            Ref<Object> obj = read_object(doc, child, kind->second);
            std::string name = has_attr(child, "name") ? attr(doc, child, "name") : next_arg_name();
            props.set_object(name, obj, where(doc, child));
        } else if (tag == "ref") {
            check_attributes(doc, child, {"id", "name"});
            std::string id = attr(doc, child, "id");
            auto it = ids_.find(id);
            if (it == ids_.end()) throw SceneError(where(doc, child), "reference to unknown id \"" + id + "\" (ids must be defined before use)");
            std::string name = has_attr(child, "name") ? attr(doc, child, "name") : next_arg_name();
            props.set_object(name, it->second, where(doc, child));
        } else if (tag == "default") {
            if (!in_scene) throw SceneError(where(doc, child), "<default> may only appear directly inside <scene>");
            check_attributes(doc, child, {"name", "value"});
            std::string name = child.attribute("name").value();
            if (!child.attribute("name") || !child.attribute("value"))
                throw SceneError(where(doc, child), "<default> needs name and value");
            if (!params_.count(name)) params_[name] = substitute(doc, child, child.attribute("value").value());
        } else if (tag == "include") {
            if (!in_scene) throw SceneError(where(doc, child), "<include> may only appear directly inside <scene>");
            check_attributes(doc, child, {"filename"});
            include(doc, child, props, depth);
        } else {
            read_property(doc, child, props);
        }
    }

    std::string next_arg_name() { return "_arg" + std::to_string(arg_counter_++); }

    void include(Document& doc, const pugi::xml_node& node, Properties& scene_props, int depth) {
        if (depth + 1 > MaxIncludeDepth) throw SceneError(where(doc, node), "includes nest too deeply (a cycle?)");
        std::string name = attr(doc, node, "filename");
        fs::path p(name);
        if (p.is_relative()) p = fs::path(doc.path).parent_path() / p;
        std::ifstream in(p, std::ios::binary);
        std::error_code ec;
        if (!in || fs::is_directory(p, ec)) throw SceneError(where(doc, node), "cannot open included file \"" + name + "\"");
        std::stringstream ss;
        ss << in.rdbuf();
        Document& inc = parse_document(ss.str(), p.string(), where(doc, node));
        read_scene_element(inc, inc.xml.document_element(), scene_props, depth + 1);
    }

    Ref<Object> read_object(Document& doc, const pugi::xml_node& node, ObjectKind kind) {
        check_attributes(doc, node, {"type", "id", "name"});
        std::string type = attr(doc, node, "type");
        Properties props(type, where(doc, node));
        std::string id = attr_or(doc, node, "id", "");
        props.id = id;
        if (!id.empty() && ids_.count(id)) throw SceneError(where(doc, node), "duplicate id \"" + id + "\"");
        for (pugi::xml_node child : node.children()) read_child(doc, child, props, false, 0);
        Ref<Object> obj = create_plugin(kind, props);
        if (!id.empty()) ids_[id] = obj;
        return obj;
    }

    void read_property(Document& doc, const pugi::xml_node& node, Properties& props) {
        std::string tag = node.name();
        SourceLocation loc = where(doc, node);
        auto no_children = [&] {
            for (pugi::xml_node c : node.children())
                if (c.type() == pugi::node_element) throw SceneError(where(doc, c), "<" + tag + "> cannot contain <" + c.name() + ">");
        };
        if (tag == "integer") {
            check_attributes(doc, node, {"name", "value"});
            no_children();
            std::string v = trim(attr(doc, node, "value"));
            char* end = nullptr;
            long long i = std::strtoll(v.c_str(), &end, 10);
            if (v.empty() || end != v.c_str() + v.size()) throw SceneError(loc, "\"" + v + "\" is not an integer");
            props.set(attr(doc, node, "name"), Properties::Type::Integer, int64_t(i), loc);
        } else if (tag == "float") {
            check_attributes(doc, node, {"name", "value"});
            no_children();
            props.set(attr(doc, node, "name"), Properties::Type::Float, parse_double(doc, node, attr(doc, node, "value")), loc);
        } else if (tag == "boolean") {
            check_attributes(doc, node, {"name", "value"});
            no_children();
            std::string v = trim(attr(doc, node, "value"));
            std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            if (v != "true" && v != "false") throw SceneError(loc, "\"" + v + "\" is not a boolean (true or false)");
            props.set(attr(doc, node, "name"), Properties::Type::Boolean, v == "true", loc);
        } else if (tag == "string") {
            check_attributes(doc, node, {"name", "value"});
            no_children();
            props.set(attr(doc, node, "name"), Properties::Type::String, attr(doc, node, "value"), loc);
        } else if (tag == "point" || tag == "vector") {
            check_attributes(doc, node, {"name", "value", "x", "y", "z"});
            no_children();
            props.set(attr(doc, node, "name"), tag == "point" ? Properties::Type::Point : Properties::Type::Vector,
                      parse_vec3(doc, node, 0.0f), loc);
        } else if (tag == "rgb" || tag == "spectrum") {
            check_attributes(doc, node, {"name", "value"});
            no_children();
            auto v = parse_list(doc, node, attr(doc, node, "value"));
            Spectrum s;
            if (v.size() == 1) s = Spectrum(float(v[0]));
            else if (v.size() == 3 && tag == "rgb") s = Spectrum(float(v[0]), float(v[1]), float(v[2]));
            else if (tag == "rgb") throw SceneError(loc, "<rgb> value needs 1 or 3 numbers");
            else throw SceneError(loc, "<spectrum> is supported only with a single constant value (use <rgb> for colours)");
            props.set(attr(doc, node, "name"), Properties::Type::RGB, s, loc);
        } else if (tag == "transform") {
            check_attributes(doc, node, {"name"});
            props.set(attr(doc, node, "name"), Properties::Type::Transform, read_transform(doc, node), loc);
        } else if (tag == "translate" || tag == "rotate" || tag == "scale" || tag == "matrix" || tag == "lookat") {
            throw SceneError(loc, "<" + tag + "> must be inside a <transform>");
        } else {
            throw SceneError(loc, "unknown element <" + tag + ">");
        }
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
            } else if (tag == "lookat") {
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
    std::map<std::string, Ref<Object>> ids_;
    int arg_counter_ = 0;
};

}  // namespace

Ref<Scene> load_scene(const std::string& path, const SceneParameters& defines) {
    std::ifstream in(path, std::ios::binary);
    std::error_code ec;
    if (!in || fs::is_directory(path, ec)) throw SceneError(SourceLocation{path, 0}, "cannot open scene file");
    std::stringstream ss;
    ss << in.rdbuf();
    XmlLoader loader(defines);
    auto scene = loader.load(ss.str(), path);
    return scene;
}

Ref<Scene> load_scene_from_string(const std::string& xml, const std::string& virtual_path, const SceneParameters& defines) {
    XmlLoader loader(defines);
    return loader.load(xml, virtual_path);
}

}  // namespace candela
