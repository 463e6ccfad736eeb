// The one libFuzzer driver behind every target in fuzz/ (see fuzz/CMakeLists.txt and README
// "Sanitizers and fuzzing"). Each target is compiled from this file with
//   CANDELA_FUZZ_TEMPLATE    a scene file that names the input as $file (and its extension as
//                            $extension), or "" for the scene
//                            target, whose input is the scene text itself
//   CANDELA_FUZZ_EXTENSIONS  the file extensions the input is written with, comma-separated;
//                            with several, the input's first byte chooses one (for the image
//                            target: which decoder reads it)
//   CANDELA_FUZZ_ASSETS      the directory relative paths resolve in (fuzz/assets: small meshes
//                            and textures under the names the project's scenes use); the file
//                            resolver is confined to it and the input's private directory
//
// The contract under test is the project's rule for bad input: loading either succeeds or throws
// SceneError / InputError. Any other exception escapes and libFuzzer reports it as a crash, as it
// does sanitizer findings, time-outs (a hang) and allocations beyond -malloc_limit_mb. A scene
// that loads and has a small film is then rendered at one sample per pixel, and a non-finite
// pixel is a crash too.

#include "core/error.h"
#include "core/file_resolver.h"
#include "core/image.h"
#include "core/integrator.h"
#include "core/scene.h"
#include "core/xml.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace candela;

namespace {

// Renders bigger than this many pixels are skipped: they cost time without reaching new code.
constexpr long MaxRenderPixels = 32 * 32;

struct Target {
    std::string scene_template;  // empty: the input is the scene
    std::vector<std::string> extensions;
    fs::path work_dir;  // where the input file is written
};

Target& target() {
    static Target t;
    return t;
}

std::vector<std::string> split_commas(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

void remove_work_dir() {
    std::error_code ec;
    fs::remove_all(target().work_dir, ec);
}

// The input file lives in a private directory whose entries link to the assets, so that a
// template's or a fuzzed scene's relative paths reach them as they would beside a scene file.
void make_work_dir() {
    std::string pattern = (fs::temp_directory_path() / "candela-fuzz-XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
        std::perror("candela fuzz: mkdtemp");
        std::abort();
    }
    Target& t = target();
    t.work_dir = pattern;
    for (const auto& entry : fs::directory_iterator(CANDELA_FUZZ_ASSETS))
        fs::create_symlink(entry.path(), t.work_dir / entry.path().filename());
    std::atexit(remove_work_dir);
    // A fuzzed scene names files: <include>, meshes, images, spectra. Only the work directory
    // and the assets are reachable, never /proc, /etc or the files of whoever runs the fuzzer.
    FileResolver::confine_to({t.work_dir, CANDELA_FUZZ_ASSETS});
}

void check_finite(const Image& image) {
    for (float v : image.data())
        if (!std::isfinite(v)) {
            std::fprintf(stderr, "candela fuzz: the render holds a non-finite value\n");
            std::abort();
        }
}

void render_if_small(const Scene& scene) {
    Vec2i size = scene.sensor().film().crop_size();
    if (long(size.x) * long(size.y) > MaxRenderPixels) return;
    RenderOptions options;
    options.spp = 1;
    options.seed = 1;
    options.threads = 1;
    check_finite(scene.integrator().render(scene, options).image);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    Target& t = target();
    std::string template_path = CANDELA_FUZZ_TEMPLATE;
    if (!template_path.empty()) {
        std::ifstream in(template_path, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        t.scene_template = ss.str();
        if (t.scene_template.empty()) {
            std::fprintf(stderr, "candela fuzz: cannot read %s\n", template_path.c_str());
            std::abort();
        }
    }
    t.extensions = split_commas(CANDELA_FUZZ_EXTENSIONS);
    make_work_dir();
    // Scenes may name images; the module that reads them is loaded once, here, not inside the
    // first input that needs it (core/image.h).
    load_image_module();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const Target& t = target();
    std::string bytes(reinterpret_cast<const char*>(data), size);
    std::string extension = t.extensions.front();
    if (t.extensions.size() > 1) {
        if (bytes.empty()) return 0;
        extension = t.extensions[static_cast<unsigned char>(bytes[0]) % t.extensions.size()];
        bytes.erase(0, 1);
    }
    try {
        Ref<Scene> scene;
        if (t.scene_template.empty()) {
            scene = load_scene_from_string(bytes, (t.work_dir / ("scene." + extension)).string());
        } else {
            std::string name = "input." + extension;
            std::ofstream(t.work_dir / name, std::ios::binary | std::ios::trunc) << bytes;
            scene =
                load_scene_from_string(t.scene_template, (t.work_dir / "scene.xml").string(), {{"file", name}, {"extension", extension}});
        }
        render_if_small(*scene);
    } catch (const SceneError&) {
    } catch (const InputError&) {}
    return 0;
}
