#pragma once
// Validation against reference renders (what `candela validate` does): find the scenes that have
// a reference, render each, judge agreement by the criteria of scenes/validation/README.md
// (image_metrics.h), run the per-pixel z-test as a map of where to look, and write one
// self-contained HTML report with every image embedded.

#include "analysis/image_metrics.h"

#include "core/variant.h"

#include <string>
#include <vector>

namespace candela {

// A scene and the reference it is compared with.
struct ValidationCase {
    std::string name, scene_path, reference_path;
};
// The cases in `dir`, sorted by name: every DIR/NAME.xml or DIR/scenes/NAME.xml that has a
// reference DIR/refs/NAME.exr. InputError when `dir` is not a directory, holds no case, or
// names a scene in both places.
std::vector<ValidationCase> find_validation_cases(const std::string& dir);

struct ValidationSettings {
    int spp = 0;               // 0: each scene's own sample count
    std::string sampler;       // "" : each scene's own sampler
    int reference_spp = 2048;  // the references' sample count, for their variance in the z-test
    int threads = 0;
    int64_t seed = -1;  // -1: each scene's sampler's seed
    Variant variant = Variant::ScalarRGB;
    AgreementThresholds thresholds;
    double alpha = 0.01;  // family-wise significance of the per-pixel z-test
};

struct SceneValidation {
    std::string name;
    bool pass = false;
    bool compared = false;  // false: the scene or its reference could not be read, or their sizes differ (see reason)
    std::string reason;     // why it failed
    ImageComparison metrics;
    PixelZTest z;
    double seconds = 0.0;
    int spp = 0;
    std::string render_png, reference_png, heatmap_png, zmap_png;  // encoded images for the report
};

// Renders one case (with the variance AOV) and compares it with its reference. A scene that cannot
// be loaded, or a reference that cannot be read or has another size than the scene's film, fails
// that case (compared false, the reason said) without stopping the others.
SceneValidation validate_scene(const ValidationCase& c, const ValidationSettings& settings);

// The whole report: criteria, a summary table, then per scene the images and metrics.
std::string validation_report_html(const std::vector<SceneValidation>& scenes, const ValidationSettings& settings);

}  // namespace candela
