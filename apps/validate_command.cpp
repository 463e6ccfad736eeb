// candela validate DIR [--spp N] [-o report.html] [--reference-spp 2048]
//
// Renders every scene NAME.xml in DIR that has a reference refs/NAME.exr (the layout of the
// validation set), compares them by the validation criteria (channel means within 1%, 16x16
// block luminance within 2%), runs a per-pixel z-test with the render's own variance, and writes
// one self-contained HTML report: a summary table, then per scene Candela's image, the
// reference and a relative-difference heatmap with a legend, and the metrics. The exit code is 0
// when every scene passes, 1 otherwise.

#include "apps/commands.h"

#include "core/error.h"
#include "core/file_output.h"
#include "analysis/image_metrics.h"
#include "core/scene.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace candela::app {

namespace {

struct ValidateArgs {
    std::string dir, report = "validation-report.html";
    int spp = 0, reference_spp = 2048, threads = 0;
    double mean_tol = 0.01, block_tol = 0.02, alpha = 0.01;
    bool quiet = false;
};

struct SceneReport {
    std::string name;
    bool pass = false;
    std::string reason;
    ImageComparison metrics;
    PixelZTest z;
    double seconds = 0.0;
    int spp = 0;
    std::string render_png, reference_png, heatmap_png, zmap_png;
};

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
    return "<img alt=\"" + alt + "\" src=\"data:image/png;base64," + base64(png) + "\">";
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string html_report(const std::vector<SceneReport>& scenes, const ValidateArgs& a) {
    std::ostringstream o;
    int passed = 0;
    for (const auto& s : scenes) passed += s.pass;
    o << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Candela validation report</title>\n<style>\n"
         "body{font-family:sans-serif;margin:2em;color:#222} table{border-collapse:collapse;margin:1em 0} "
         "td,th{border:1px solid #ccc;padding:4px 10px;text-align:right} th{background:#f0f0f0} td.name{text-align:left} "
         ".pass{color:#1a7f37;font-weight:bold} .fail{color:#c62828;font-weight:bold} figure{display:inline-block;margin:0 1em 1em 0;vertical-align:top} "
         "figcaption{text-align:center;font-size:90%} img{image-rendering:pixelated} section{border-top:2px solid #ddd;padding-top:1em;margin-top:2em}\n"
         "</style></head><body>\n";
    o << "<h1>Candela validation report</h1>\n<p>" << passed << " of " << scenes.size() << " scenes pass. Criteria: every channel's whole-image mean within "
      << a.mean_tol * 100 << "% of the reference's; 16x16-block luminance within " << a.block_tol * 100
      << "% mean absolute relative difference (blocks darker than 1% of the image mean left out). The per-pixel z-test uses Candela's own variance "
         "(reference variance estimated for "
      << a.reference_spp << " spp, plus a float32 rounding floor of 1e-4 relative) with Sidak-corrected significance " << a.alpha
      << " over all pixels and channels. It is reported as a map of where to look, not used for the verdict: Monte Carlo pixel estimates are "
         "heavy-tailed, and a sample variance cannot see rare bright paths that its samples missed, so between two correct renderers it rejects "
         "more often than its nominal level (the fraction beyond |z| = 3 would be 0.27% for Gaussian noise).</p>\n";
    o << "<table><tr><th>scene</th><th>verdict</th><th>spp</th><th>mean R</th><th>mean G</th><th>mean B</th><th>block MARE</th><th>z-test rejections</th><th>max |z|</th><th>time</th></tr>\n";
    for (const auto& s : scenes) {
        o << "<tr><td class=\"name\"><a href=\"#" << s.name << "\">" << s.name << "</a></td><td class=\"" << (s.pass ? "pass\">pass" : "fail\">FAIL") << "</td><td>"
          << s.spp << "</td>";
        for (int c = 0; c < 3; ++c) o << "<td>" << fmt("%+.3f%%", 100.0 * s.metrics.mean_relative_difference[c]) << "</td>";
        o << "<td>" << fmt("%.3f%%", 100.0 * s.metrics.block_mare) << "</td><td>" << s.z.rejected << " / " << s.z.tested << "</td><td>" << fmt("%.2f", s.z.max_abs_z)
          << "</td><td>" << fmt("%.1f s", s.seconds) << "</td></tr>\n";
    }
    o << "</table>\n";
    for (const auto& s : scenes) {
        o << "<section id=\"" << s.name << "\"><h2>" << s.name << " <span class=\"" << (s.pass ? "pass\">pass" : "fail\">FAIL") << "</span></h2>\n";
        if (!s.pass) o << "<p class=\"fail\">" << s.reason << "</p>\n";
        o << "<figure>" << img_tag(s.render_png, s.name + " rendered by Candela") << "<figcaption>Candela, " << s.spp << " spp</figcaption></figure>\n";
        o << "<figure>" << img_tag(s.reference_png, s.name + " reference") << "<figcaption>reference</figcaption></figure>\n";
        o << "<figure>" << img_tag(s.heatmap_png, s.name + " relative difference") << "<figcaption>relative luminance difference (Candela - reference) / reference</figcaption></figure>\n";
        o << "<figure>" << img_tag(s.zmap_png, s.name + " z map") << "<figcaption>per-pixel |z| (largest over RGB)</figcaption></figure>\n";
        o << "<table><tr><th></th><th>R</th><th>G</th><th>B</th></tr>\n";
        o << "<tr><td class=\"name\">mean, Candela</td><td>" << fmt("%.6g", s.metrics.mean_test.x) << "</td><td>" << fmt("%.6g", s.metrics.mean_test.y) << "</td><td>"
          << fmt("%.6g", s.metrics.mean_test.z) << "</td></tr>\n";
        o << "<tr><td class=\"name\">mean, reference</td><td>" << fmt("%.6g", s.metrics.mean_reference.x) << "</td><td>" << fmt("%.6g", s.metrics.mean_reference.y)
          << "</td><td>" << fmt("%.6g", s.metrics.mean_reference.z) << "</td></tr>\n";
        o << "<tr><td class=\"name\">relative difference</td>";
        for (int c = 0; c < 3; ++c) o << "<td>" << fmt("%+.3f%%", 100.0 * s.metrics.mean_relative_difference[c]) << "</td>";
        o << "</tr></table>\n<table>";
        o << "<tr><td class=\"name\">block MARE (16x16 luminance)</td><td>" << fmt("%.3f%%", 100.0 * s.metrics.block_mare) << " over " << s.metrics.blocks_used << " of "
          << s.metrics.blocks_total << " blocks</td></tr>\n";
        o << "<tr><td class=\"name\">RMSE / relMSE / MARE</td><td>" << fmt("%.4g", s.metrics.rmse) << " / " << fmt("%.4g", s.metrics.relmse) << " / "
          << fmt("%.4g", s.metrics.mare) << "</td></tr>\n";
        o << "<tr><td class=\"name\">per-pixel z-test</td><td>" << s.z.rejected << " of " << s.z.tested << " pixel channels beyond |z| = " << fmt("%.2f", s.z.threshold)
          << "; max |z| " << fmt("%.2f", s.z.max_abs_z) << "; " << fmt("%.3f%%", 100.0 * s.z.fraction_beyond_3)
          << " beyond |z| = 3 (0.27% for Gaussian noise)</td></tr>\n";
        o << "<tr><td class=\"name\">render time</td><td>" << fmt("%.2f s", s.seconds) << "</td></tr></table>\n</section>\n";
    }
    o << "</body></html>\n";
    return o.str();
}

}  // namespace

void add_validate_command(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<ValidateArgs>();
    CLI::App* cmd = app.add_subcommand("validate", "Render every scene with a reference in DIR and report agreement as HTML");
    cmd->add_option("dir", a->dir, "Directory with NAME.xml scenes and refs/NAME.exr references")->required();
    cmd->add_option("-o,--output", a->report, "HTML report to write (default validation-report.html)");
    cmd->add_option("--spp", a->spp, "Samples per pixel (default: each scene's own)")->check(CLI::PositiveNumber);
    cmd->add_option("--reference-spp", a->reference_spp, "Samples per pixel of the references, for their variance (default 2048)")->check(CLI::PositiveNumber);
    cmd->add_option("--mean-tolerance", a->mean_tol, "Channel mean tolerance (default 0.01)")->check(CLI::PositiveNumber);
    cmd->add_option("--block-tolerance", a->block_tol, "Block luminance tolerance (default 0.02)")->check(CLI::PositiveNumber);
    cmd->add_option("--threads,-t", a->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
    cmd->add_flag("--quiet,-q", a->quiet, "Only the summary line");
    cmd->callback([a, &run] {
        run = [a] {
            check_output_path(a->report);
            if (!fs::is_directory(a->dir)) throw InputError(a->dir + ": not a directory");
            std::vector<std::string> names;
            for (const auto& entry : fs::directory_iterator(a->dir)) {
                fs::path p = entry.path();
                if (p.extension() == ".xml" && fs::exists(fs::path(a->dir) / "refs" / (p.stem().string() + ".exr"))) names.push_back(p.stem().string());
            }
            std::sort(names.begin(), names.end());
            if (names.empty()) throw InputError(a->dir + ": no NAME.xml with a refs/NAME.exr");
            std::vector<SceneReport> reports;
            AgreementThresholds thresholds{a->mean_tol, a->block_tol};
            for (const std::string& name : names) {
                SceneReport r;
                r.name = name;
                Ref<Scene> scene = load_scene((fs::path(a->dir) / (name + ".xml")).string());
                Image reference = read_image((fs::path(a->dir) / "refs" / (name + ".exr")).string());
                RenderOptions o;
                o.spp = a->spp;
                o.threads = a->threads;
                o.aovs = {"variance"};
                RenderResult result = scene->integrator().render(*scene, o);
                r.seconds = result.stats.seconds;
                r.spp = result.stats.spp;
                r.metrics = compare_images(result.image, reference);
                r.pass = images_agree(r.metrics, thresholds, &r.reason);
                Image z_map;
                r.z = pixel_z_test(result.image, reference, r.spp, a->reference_spp, a->alpha, &z_map);
                r.zmap_png = encode_png(z_map);
                r.render_png = encode_png(tonemap_srgb(result.image));
                r.reference_png = encode_png(tonemap_srgb(reference));
                r.heatmap_png = encode_png(relative_difference_heatmap(result.image, reference));
                if (!a->quiet)
                    std::printf("%-12s %s  means %+.3f%% %+.3f%% %+.3f%%, block %.3f%%, z-test %lld/%lld beyond %.2f (max %.1f), %.1fs%s%s\n", name.c_str(),
                                r.pass ? "pass" : "FAIL", 100 * r.metrics.mean_relative_difference.x, 100 * r.metrics.mean_relative_difference.y,
                                100 * r.metrics.mean_relative_difference.z, 100 * r.metrics.block_mare, r.z.rejected, r.z.tested, r.z.threshold, r.z.max_abs_z,
                                r.seconds, r.pass ? "" : ": ", r.reason.c_str());
                reports.push_back(std::move(r));
            }
            write_file_atomically(a->report, html_report(reports, *a));
            int passed = 0;
            for (const auto& r : reports) passed += r.pass;
            std::printf("%d of %zu scenes pass; report: %s\n", passed, reports.size(), a->report.c_str());
            return passed == int(reports.size()) ? ExitOk : ExitCheckFailed;
        };
    });
}

}  // namespace candela::app
