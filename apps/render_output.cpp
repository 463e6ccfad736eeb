#include "apps/render_output.h"

#include "core/progress.h"
#include "core/scene.h"

#include <candela/version.h>

#include <cstdio>

namespace candela {

void annotate_render(RenderResult& result, const Scene& scene, const std::string& scene_path) {
    const RenderStats& s = result.stats;
    auto& m = result.image.metadata;
    m["software"] = std::string("Candela ") + CANDELA_VERSION;
    m["candela.version"] = CANDELA_VERSION;
    m["candela.scene"] = scene_path;
    m["candela.integrator"] = scene.integrator().to_string();
    m["candela.spp"] = std::to_string(s.spp);
    m["candela.seed"] = std::to_string(s.seed);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3f", s.seconds);
    m["candela.renderTime"] = buf;
    m["candela.samples"] = std::to_string(s.samples);
    m["candela.rays"] = std::to_string(s.rays);
    m["candela.nonfiniteSamples"] = std::to_string(s.nonfinite);
    m["candela.partial"] = s.partial ? "true" : "false";
}

std::string render_summary(const RenderStats& s, const std::string& output) {
    char buf[256];
    if (s.single_frame) {
        std::snprintf(buf, sizeof buf, "wrote %s: %.1f ms per frame, %d sample%s per pixel%s", output.c_str(), s.seconds * 1e3, s.spp,
                      s.spp == 1 ? "" : "s", s.partial ? " (partial)" : "");
        return buf;
    }
    double t = std::max(s.seconds, 1e-9);
    std::snprintf(buf, sizeof buf, "wrote %s: %s, %d spp, %s samples/s, %.2f Mrays/s%s", output.c_str(),
                  format_duration(s.seconds).c_str(), s.spp, format_count(double(s.samples) / t).c_str(),
                  double(s.rays) / t * 1e-6, s.partial ? " (partial)" : "");
    return buf;
}

}  // namespace candela
