#pragma once
// Rendering one scene by several methods and comparing each with a converged path-traced
// reference (what `candela compare-modes` does, and the Python API's candela.compare_modes): the
// methods, the reference, the table of times and errors, and the contact sheet.
//
// A method is an integrator by its registered name (raster, radiosity, path, ao, direct, sppm,
// photonmapper, ...), with optional parameters as NAME:key=value:key=value (a value reads as an
// integer, a number, true/false, or else text; an rgb parameter takes one grey number). Two
// shorthands: `raster-gi` is raster with ao=16, `baked` is raster with lighting=baked. `path`
// without parameters is the scene's own path tracer when it has one.

#include "analysis/image_metrics.h"
#include "core/integrator.h"

#include <functional>
#include <string>
#include <vector>

namespace candela {

class Scene;
struct RasterSettings;

// The methods of a comma-separated list; InputError for an empty one.
std::vector<std::string> split_methods(const std::string& list);
// The methods compared when none are named: raster-gi is left out, as on a scene without an
// environment or ambient light it renders the raster image again.
constexpr const char* DefaultComparedMethods = "raster,baked,radiosity,path";
// The integrator of one method (null: the scene's own); `adjust_raster` (may be empty) applies
// settings to every raster method. InputError or SceneError naming the method when it is wrong.
Ref<Integrator> method_integrator(const std::string& spec, const Scene& scene,
                                  const std::function<void(RasterSettings&)>& adjust_raster = nullptr);

// The converged reference: the scene's path tracer (or a default one) at `spp` with a seed of its
// own, so that its noise is independent of the `path` method's. Linear RGB.
RenderResult reference_render(Scene& scene, int spp, int threads);

struct MethodRun {
    std::string label;
    RenderResult result;  // linear RGB
    double bake_seconds = 0.0;
    ImageComparison comparison;  // against the reference
};
// Renders one method (spp 0: the scene's) and compares it with `reference`.
MethodRun run_method(const std::string& spec, const Ref<Integrator>& integrator, Scene& scene, int spp, int threads,
                     const Image& reference);

// (mean luminance - reference's) / reference's.
double mean_luminance_difference(const ImageComparison& c);
// The Markdown table: per method its time, baking time, mean luminance difference, relMSE, MARE
// and block MARE; `reference_label` ends it ("path tracer, 1024 spp, 3.1 s", a file name).
std::string methods_table(const std::vector<MethodRun>& runs, const std::string& reference_label);
// The picture: the reference, then per method its image above its relative-difference heatmap
// (full colour at `heatmap_range`), each captioned with its figures.
Image methods_contact_sheet(const std::vector<MethodRun>& runs, const RenderResult& reference,
                            const std::vector<std::string>& reference_caption, float heatmap_range);

}  // namespace candela
