#include "analysis/validation.h"

#include "core/error.h"
#include "core/scene.h"
#include "core/text.h"
#include "core/xml.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace candela {

namespace {

std::string base64(const std::string& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        unsigned v = (unsigned char)bytes[i] << 16;
        if (i + 1 < bytes.size()) v |= (unsigned char)bytes[i + 1] << 8;
        if (i + 2 < bytes.size()) v |= (unsigned char)bytes[i + 2];
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

std::string img_tag(const std::string& png, const std::string& alt) {
    return "<img alt=\"" + escape_markup(alt) + "\" src=\"data:image/png;base64," + base64(png) + "\">";
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// Adds the cases NAME.xml in `scenes` that have `refs`/NAME.exr.
void add_cases(const fs::path& scenes, const fs::path& refs, std::vector<ValidationCase>& cases) {
    if (!fs::is_directory(scenes)) return;
    for (const auto& entry : fs::directory_iterator(scenes)) {
        fs::path p = entry.path();
        fs::path ref = refs / (p.stem().string() + ".exr");
        if (p.extension() == ".xml" && fs::exists(ref)) cases.push_back({p.stem().string(), p.string(), ref.string()});
    }
}

// Sections are named by their position, not by the scene's file name (which may hold any
// character); every name and reason in the report goes through escape_markup.
std::string section_id(size_t index) { return "scene-" + std::to_string(index + 1); }

void write_head(std::ostringstream& o) {
    o << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Candela validation report</title>\n<style>\n"
         "body{font-family:sans-serif;margin:2em;color:#222} table{border-collapse:collapse;margin:1em 0} "
         "td,th{border:1px solid #ccc;padding:4px 10px;text-align:right} th{background:#f0f0f0} td.name{text-align:left} "
         ".pass{color:#1a7f37;font-weight:bold} .fail{color:#c62828;font-weight:bold} figure{display:inline-block;margin:0 1em 1em 0;vertical-align:top} "
         "figcaption{text-align:center;font-size:90%} img{image-rendering:pixelated} section{border-top:2px solid #ddd;padding-top:1em;margin-top:2em}\n"
         "</style></head><body>\n";
}

void write_summary(std::ostringstream& o, const std::vector<SceneValidation>& scenes, const ValidationSettings& a) {
    int passed = 0;
    for (const auto& s : scenes) passed += s.pass;
    o << "<h1>Candela validation report</h1>\n<p>" << passed << " of " << scenes.size()
      << " scenes pass. Criteria: every channel's whole-image mean within " << a.thresholds.mean * 100
      << "% of the reference's; 16x16-block luminance within " << a.thresholds.block * 100
      << "% mean absolute relative difference (blocks darker than 1% of the image mean left out). The per-pixel z-test uses Candela's own variance "
         "(reference variance estimated for "
      << a.reference_spp << " spp, plus a float32 rounding floor of 1e-4 relative) with Sidak-corrected significance " << a.alpha
      << " over all pixels and channels. It is reported as a map of where to look, not used for the verdict: Monte Carlo pixel estimates are "
         "heavy-tailed, and a sample variance cannot see rare bright paths that its samples missed, so between two correct renderers it rejects "
         "more often than its nominal level (the fraction beyond |z| = 3 would be 0.27% for Gaussian noise).</p>\n";
    o << "<table><tr><th>scene</th><th>verdict</th><th>spp</th><th>mean R</th><th>mean G</th><th>mean B</th><th>block MARE</th><th>z-test rejections</th><th>max |z|</th><th>time</th></tr>\n";
    for (size_t i = 0; i < scenes.size(); ++i) {
        const SceneValidation& s = scenes[i];
        o << "<tr><td class=\"name\"><a href=\"#" << section_id(i) << "\">" << escape_markup(s.name) << "</a></td><td class=\""
          << (s.pass ? "pass\">pass" : "fail\">FAIL") << "</td>";
        if (!s.compared) {
            o << "<td colspan=\"8\" class=\"name\">not compared: " << escape_markup(s.reason) << "</td></tr>\n";
            continue;
        }
        o << "<td>" << s.spp << "</td>";
        for (int c = 0; c < 3; ++c) o << "<td>" << fmt("%+.3f%%", 100.0 * s.metrics.mean_relative_difference[c]) << "</td>";
        o << "<td>" << fmt("%.3f%%", 100.0 * s.metrics.block_mare) << "</td><td>" << s.z.rejected << " / " << s.z.tested << "</td><td>"
          << fmt("%.2f", s.z.max_abs_z) << "</td><td>" << fmt("%.1f s", s.seconds) << "</td></tr>\n";
    }
    o << "</table>\n";
}

void write_scene_section(std::ostringstream& o, const SceneValidation& s, size_t index) {
    o << "<section id=\"" << section_id(index) << "\"><h2>" << escape_markup(s.name) << " <span class=\""
      << (s.pass ? "pass\">pass" : "fail\">FAIL") << "</span></h2>\n";
    if (!s.pass) o << "<p class=\"fail\">" << escape_markup(s.reason) << "</p>\n";
    if (!s.compared) {
        o << "</section>\n";
        return;
    }
    o << "<figure>" << img_tag(s.render_png, s.name + " rendered by Candela") << "<figcaption>Candela, " << s.spp
      << " spp</figcaption></figure>\n";
    o << "<figure>" << img_tag(s.reference_png, s.name + " reference") << "<figcaption>reference</figcaption></figure>\n";
    o << "<figure>" << img_tag(s.heatmap_png, s.name + " relative difference")
      << "<figcaption>relative luminance difference (Candela - reference) / reference</figcaption></figure>\n";
    o << "<figure>" << img_tag(s.zmap_png, s.name + " z map") << "<figcaption>per-pixel |z| (largest over RGB)</figcaption></figure>\n";
    o << "<table><tr><th></th><th>R</th><th>G</th><th>B</th></tr>\n";
    o << "<tr><td class=\"name\">mean, Candela</td><td>" << fmt("%.6g", s.metrics.mean_test.x) << "</td><td>"
      << fmt("%.6g", s.metrics.mean_test.y) << "</td><td>" << fmt("%.6g", s.metrics.mean_test.z) << "</td></tr>\n";
    o << "<tr><td class=\"name\">mean, reference</td><td>" << fmt("%.6g", s.metrics.mean_reference.x) << "</td><td>"
      << fmt("%.6g", s.metrics.mean_reference.y) << "</td><td>" << fmt("%.6g", s.metrics.mean_reference.z) << "</td></tr>\n";
    o << "<tr><td class=\"name\">relative difference</td>";
    for (int c = 0; c < 3; ++c) o << "<td>" << fmt("%+.3f%%", 100.0 * s.metrics.mean_relative_difference[c]) << "</td>";
    o << "</tr></table>\n<table>";
    o << "<tr><td class=\"name\">block MARE (16x16 luminance)</td><td>" << fmt("%.3f%%", 100.0 * s.metrics.block_mare) << " over "
      << s.metrics.blocks_used << " of " << s.metrics.blocks_total << " blocks</td></tr>\n";
    o << "<tr><td class=\"name\">RMSE / relMSE / MARE</td><td>" << fmt("%.4g", s.metrics.rmse) << " / " << fmt("%.4g", s.metrics.relmse)
      << " / " << fmt("%.4g", s.metrics.mare) << "</td></tr>\n";
    o << "<tr><td class=\"name\">per-pixel z-test</td><td>" << s.z.rejected << " of " << s.z.tested
      << " pixel channels beyond |z| = " << fmt("%.2f", s.z.threshold) << "; max |z| " << fmt("%.2f", s.z.max_abs_z) << "; "
      << fmt("%.3f%%", 100.0 * s.z.fraction_beyond_3) << " beyond |z| = 3 (0.27% for Gaussian noise)</td></tr>\n";
    o << "<tr><td class=\"name\">render time</td><td>" << fmt("%.2f s", s.seconds) << "</td></tr></table>\n</section>\n";
}

}  // namespace

std::vector<ValidationCase> find_validation_cases(const std::string& dir) {
    if (!fs::is_directory(dir)) throw InputError(dir + ": not a directory");
    std::vector<ValidationCase> cases;
    const fs::path refs = fs::path(dir) / "refs";
    add_cases(dir, refs, cases);
    add_cases(fs::path(dir) / "scenes", refs, cases);
    std::sort(cases.begin(), cases.end(), [](const ValidationCase& a, const ValidationCase& b) { return a.name < b.name; });
    if (cases.empty()) throw InputError(dir + ": no NAME.xml or scenes/NAME.xml with a refs/NAME.exr");
    for (size_t i = 1; i < cases.size(); ++i)
        if (cases[i].name == cases[i - 1].name)
            throw InputError(dir + ": " + cases[i].name + ".xml is both in the directory and in scenes/; which one does refs/" +
                             cases[i].name + ".exr belong to?");
    return cases;
}

SceneValidation validate_scene(const ValidationCase& c, const ValidationSettings& settings) {
    SceneValidation r;
    r.name = c.name;
    Ref<Scene> scene;
    Image reference;
    try {
        scene = load_scene(c.scene_path, {}, settings.variant);
        reference = read_image(c.reference_path);
    } catch (const SceneError& e) {
        r.reason = e.what();
        return r;
    } catch (const InputError& e) {
        r.reason = e.what();
        return r;
    }
    const Vec2i size = scene->sensor().film().crop_size();
    if (reference.width() != size.x || reference.height() != size.y) {
        r.reason = "the reference " + c.reference_path + " is " + std::to_string(reference.width()) + " x " +
                   std::to_string(reference.height()) + ", the scene renders " + std::to_string(size.x) + " x " + std::to_string(size.y);
        return r;
    }
    r.compared = true;
    RenderOptions o;
    o.spp = settings.spp;
    o.sampler = settings.sampler;
    o.threads = settings.threads;
    if (settings.seed >= 0) o.seed = uint64_t(settings.seed);
    o.aovs = {"variance"};
    RenderResult result = scene->integrator().render(*scene, o);
    r.seconds = result.stats.seconds;
    r.spp = result.stats.spp;
    r.metrics = compare_images(result.image, reference);
    r.pass = images_agree(r.metrics, settings.thresholds, &r.reason);
    Image z_map;
    r.z = pixel_z_test(result.image, reference, r.spp, settings.reference_spp, settings.alpha, &z_map);
    r.zmap_png = encode_png(z_map);
    r.render_png = encode_png(tonemap_srgb(result.image));
    r.reference_png = encode_png(tonemap_srgb(reference));
    r.heatmap_png = encode_png(relative_difference_heatmap(result.image, reference));
    return r;
}

std::string validation_report_html(const std::vector<SceneValidation>& scenes, const ValidationSettings& settings) {
    std::ostringstream o;
    write_head(o);
    write_summary(o, scenes, settings);
    for (size_t i = 0; i < scenes.size(); ++i) write_scene_section(o, scenes[i], i);
    o << "</body></html>\n";
    return o.str();
}

}  // namespace candela
