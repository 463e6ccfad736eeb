#include "apps/render_output.h"

#include "core/progress.h"
#include "core/scene.h"

#include <candela/version.h>

#include <cstdio>

namespace candela {

void annotate_render(RenderResult& result, const Scene& scene, const std::string& scene_path) {
    annotate_image(result.image, result.stats, scene.integrator().to_string(), scene_path);
}

std::string render_summary(const RenderStats& s, const std::string& output, const std::string& samples) {
    char buf[256];
    if (s.single_frame) {
        std::snprintf(buf, sizeof buf, "wrote %s: %.1f ms per frame, %d sample%s per pixel%s", output.c_str(), s.seconds * 1e3, s.spp,
                      s.spp == 1 ? "" : "s", s.partial ? " (partial)" : "");
        return buf;
    }
    double t = std::max(s.seconds, 1e-9);
    const std::string spp = samples.empty() ? std::to_string(s.spp) + " spp" : samples;
    std::snprintf(buf, sizeof buf, "wrote %s: %s, %s, %s samples/s, %.2f Mrays/s%s", output.c_str(), format_duration(s.seconds).c_str(),
                  spp.c_str(), format_count(double(s.samples) / t).c_str(), double(s.rays) / t * 1e-6, s.partial ? " (partial)" : "");
    return buf;
}

}  // namespace candela
