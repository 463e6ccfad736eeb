#pragma once
// What a finished render records about itself: EXR metadata and the summary line.

#include "core/integrator.h"

#include <string>

namespace candela {

class Scene;

// Adds metadata to result.image: scene file, spp, seed, render time, samples, rays, dropped
// non-finite samples, whether the render was interrupted, and the Candela version.
void annotate_render(RenderResult& result, const Scene& scene, const std::string& scene_path);
// "wrote out.exr: 12.3s, 64 spp, 4.1M samples/s, 31.2 Mrays/s", or for a single rasterized
// frame "wrote out.exr: 85.2 ms per frame, 4 samples per pixel". `samples` replaces "64 spp"
// when not empty (a part: "samples 0:8 of 16").
std::string render_summary(const RenderStats& stats, const std::string& output, const std::string& samples = "");

}  // namespace candela
