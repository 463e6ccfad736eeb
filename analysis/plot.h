#pragma once
// Log-log line plots (convergence curves) written as SVG or as a PNG image.

#include "core/image.h"

#include <string>
#include <vector>

namespace candela {

struct PlotSeries {
    std::string label;
    std::vector<double> x, y;
    Spectrum color{0.1f, 0.3f, 0.8f};
    bool dashed = false;
    bool markers = true;
};

struct LogLogPlot {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;

    // By extension: ".svg" writes SVG, anything else a PNG.
    void write(const std::string& path) const;
    std::string svg() const;
    Image image(int width = 640, int height = 420) const;
};

}  // namespace candela
