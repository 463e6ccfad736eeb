#include "analysis/plot.h"

#include "core/file_output.h"
#include "core/image_draw.h"
#include "core/text.h"
#include "geometry2d/raster2d.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

namespace candela {

namespace {

// Axis range in decades covering all positive data.
struct Range {
    double lo = 0.0, hi = 1.0;  // log10
};

Range decades(const std::vector<PlotSeries>& series, bool use_x) {
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& s : series)
        for (double v : use_x ? s.x : s.y)
            if (v > 0.0 && std::isfinite(v)) {
                lo = std::min(lo, std::log10(v));
                hi = std::max(hi, std::log10(v));
            }
    if (!std::isfinite(lo)) return {0.0, 1.0};
    Range r{std::floor(lo), std::ceil(hi)};
    if (r.hi <= r.lo) r.hi = r.lo + 1.0;
    return r;
}

std::string power_label(int e) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "1E%d", e);
    return buf;
}

constexpr int Left = 70, Right = 150, Top = 40, Bottom = 50;

}  // namespace

std::string LogLogPlot::svg() const {
    const int w = 640, h = 420, pw = w - Left - Right, ph = h - Top - Bottom;
    Range rx = decades(series, true), ry = decades(series, false);
    auto px = [&](double v) { return Left + (std::log10(v) - rx.lo) / (rx.hi - rx.lo) * pw; };
    auto py = [&](double v) { return Top + ph - (std::log10(v) - ry.lo) / (ry.hi - ry.lo) * ph; };
    auto rgb = [](const Spectrum& c) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "rgb(%d,%d,%d)", int(255 * c.x), int(255 * c.y), int(255 * c.z));
        return std::string(buf);
    };
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    o << "<text x=\"" << w / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << escape_markup(title) << "</text>\n";
    for (int e = int(rx.lo); e <= int(rx.hi); ++e) {
        double x = px(std::pow(10.0, e));
        o << "<line x1=\"" << x << "\" y1=\"" << Top << "\" x2=\"" << x << "\" y2=\"" << Top + ph << "\" stroke=\"#ddd\"/>\n";
        o << "<text x=\"" << x << "\" y=\"" << Top + ph + 16 << "\" text-anchor=\"middle\">10<tspan dy=\"-6\" font-size=\"9\">" << e
          << "</tspan></text>\n";
    }
    for (int e = int(ry.lo); e <= int(ry.hi); ++e) {
        double y = py(std::pow(10.0, e));
        o << "<line x1=\"" << Left << "\" y1=\"" << y << "\" x2=\"" << Left + pw << "\" y2=\"" << y << "\" stroke=\"#ddd\"/>\n";
        o << "<text x=\"" << Left - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">10<tspan dy=\"-6\" font-size=\"9\">" << e
          << "</tspan></text>\n";
    }
    o << "<rect x=\"" << Left << "\" y=\"" << Top << "\" width=\"" << pw << "\" height=\"" << ph << "\" fill=\"none\" stroke=\"black\"/>\n";
    o << "<text x=\"" << Left + pw / 2 << "\" y=\"" << h - 12 << "\" text-anchor=\"middle\">" << escape_markup(x_label) << "</text>\n";
    o << "<text x=\"16\" y=\"" << Top + ph / 2 << "\" text-anchor=\"middle\" transform=\"rotate(-90 16 " << Top + ph / 2 << ")\">"
      << escape_markup(y_label) << "</text>\n";
    int legend_y = Top + 10;
    for (const auto& s : series) {
        std::ostringstream pts;
        for (size_t i = 0; i < s.x.size(); ++i)
            if (s.x[i] > 0 && s.y[i] > 0) pts << px(s.x[i]) << "," << py(s.y[i]) << " ";
        o << "<polyline points=\"" << pts.str() << "\" fill=\"none\" stroke=\"" << rgb(s.color) << "\" stroke-width=\"2\""
          << (s.dashed ? " stroke-dasharray=\"6,4\"" : "") << "/>\n";
        if (s.markers)
            for (size_t i = 0; i < s.x.size(); ++i)
                if (s.x[i] > 0 && s.y[i] > 0)
                    o << "<circle cx=\"" << px(s.x[i]) << "\" cy=\"" << py(s.y[i]) << "\" r=\"3.5\" fill=\"" << rgb(s.color) << "\"/>\n";
        o << "<line x1=\"" << Left + pw + 10 << "\" y1=\"" << legend_y << "\" x2=\"" << Left + pw + 30 << "\" y2=\"" << legend_y
          << "\" stroke=\"" << rgb(s.color) << "\" stroke-width=\"2\"" << (s.dashed ? " stroke-dasharray=\"6,4\"" : "") << "/>\n";
        o << "<text x=\"" << Left + pw + 34 << "\" y=\"" << legend_y + 4 << "\">" << escape_markup(s.label) << "</text>\n";
        legend_y += 18;
    }
    o << "</svg>\n";
    return o.str();
}

Image LogLogPlot::image(int w, int h) const {
    const int pw = w - Left - Right, ph = h - Top - Bottom;
    Range rx = decades(series, true), ry = decades(series, false);
    auto px = [&](double v) { return int(std::lround(Left + (std::log10(v) - rx.lo) / (rx.hi - rx.lo) * pw)); };
    auto py = [&](double v) { return int(std::lround(Top + ph - (std::log10(v) - ry.lo) / (ry.hi - ry.lo) * ph)); };
    Image img = Image::rgb(w, h);
    draw::fill_rect(img, 0, 0, w, h, Spectrum(1.0f));
    auto put = [&](int x, int y, const Spectrum& c) {
        if (x >= 0 && y >= 0 && x < w && y < h) img.set_rgb(x, y, c);
    };
    const Spectrum grid(0.87f), black(0.0f);
    for (int e = int(rx.lo); e <= int(rx.hi); ++e) {
        int x = px(std::pow(10.0, e));
        raster2d::line_bresenham(x, Top, x, Top + ph, [&](int a, int b) { put(a, b, grid); });
        std::string l = power_label(e);
        draw::text(img, x - draw::text_width(l) / 2, Top + ph + 6, l, black);
    }
    for (int e = int(ry.lo); e <= int(ry.hi); ++e) {
        int y = py(std::pow(10.0, e));
        raster2d::line_bresenham(Left, y, Left + pw, y, [&](int a, int b) { put(a, b, grid); });
        std::string l = power_label(e);
        draw::text(img, Left - 6 - draw::text_width(l), y - 3, l, black);
    }
    for (auto [x0, y0, x1, y1] : {std::array<int, 4>{Left, Top, Left + pw, Top},
                                  {Left + pw, Top, Left + pw, Top + ph},
                                  {Left + pw, Top + ph, Left, Top + ph},
                                  {Left, Top + ph, Left, Top}})
        raster2d::line_bresenham(x0, y0, x1, y1, [&](int a, int b) { put(a, b, black); });
    draw::text(img, w / 2 - draw::text_width(title) / 2, 14, title, black);
    draw::text(img, Left + pw / 2 - draw::text_width(x_label) / 2, h - 18, x_label, black);
    draw::text(img, 4, Top - 14, y_label, black);
    int legend_y = Top + 10;
    for (const auto& s : series) {
        int step = 0;
        auto plot_line = [&](int a, int b) {
            // Dashes: 6 pixels on, 4 off; lines two pixels thick.
            bool on = !s.dashed || (step++ % 10) < 6;
            if (on) {
                put(a, b, s.color);
                put(a, b + 1, s.color);
            }
        };
        for (size_t i = 0; i + 1 < s.x.size(); ++i)
            if (s.x[i] > 0 && s.y[i] > 0 && s.x[i + 1] > 0 && s.y[i + 1] > 0)
                raster2d::line_bresenham(px(s.x[i]), py(s.y[i]), px(s.x[i + 1]), py(s.y[i + 1]), plot_line);
        if (s.markers)
            for (size_t i = 0; i < s.x.size(); ++i)
                if (s.x[i] > 0 && s.y[i] > 0)
                    for (int r = 0; r <= 3; ++r)
                        raster2d::circle_midpoint(px(s.x[i]), py(s.y[i]), r, [&](int a, int b) { put(a, b, s.color); });
        step = 0;
        raster2d::line_bresenham(Left + pw + 10, legend_y, Left + pw + 30, legend_y, plot_line);
        draw::text(img, Left + pw + 34, legend_y - 3, s.label, black);
        legend_y += 16;
    }
    return img;
}

void LogLogPlot::write(const std::string& path) const {
    if (std::filesystem::path(path).extension() == ".svg")
        write_file_atomically(path, svg());
    else
        write_png_display(image(), path);
}

}  // namespace candela
