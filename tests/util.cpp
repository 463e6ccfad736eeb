#include "tests/util.h"

#include "core/scene.h"

#include <candela/image_module.h>
#include <catch2/catch.hpp>

#include <dlfcn.h>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace candela::test {

double test_effort() {
    const char* text = std::getenv("CANDELA_TEST_EFFORT");
    if (!text || !*text) return 1.0;
    char* end = nullptr;
    double effort = std::strtod(text, &end);
    if (*end || !(effort > 0.0 && effort <= 1.0)) throw std::invalid_argument("CANDELA_TEST_EFFORT must be a number in (0, 1]");
    return effort;
}

int effort_scaled(int samples, int minimum) { return std::max(minimum, int(samples * test_effort())); }

std::filesystem::path scratch_dir(const std::string& name) {
    // Per process: ctest runs test cases in parallel processes.
    std::filesystem::path p = std::filesystem::path(CANDELA_BINARY_DIR) / "test-scratch" / (name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string source_path(const std::string& relative) { return std::string(CANDELA_SOURCE_DIR) + "/" + relative; }

std::string candela_binary() { return std::string(CANDELA_BINARY_DIR) + "/candela"; }

const ImageCodecs& module_codecs() {
    static void* module = ::dlopen(CANDELA_IMAGE_MODULE, RTLD_LAZY | RTLD_LOCAL);
    REQUIRE(module != nullptr);
    auto entry = reinterpret_cast<decltype(&candela_image_codecs)>(::dlsym(module, CANDELA_IMAGE_CODECS_ENTRY));
    REQUIRE(entry != nullptr);
    const ImageCodecs* codecs = entry(ImageCodecsAbi);
    REQUIRE(codecs != nullptr);
    return *codecs;
}

int run_command(const std::string& command, const std::filesystem::path& log) {
    std::string full = "{ " + command + " ; } > '" + log.string() + "' 2>&1";
    int status = std::system(full.c_str());
    if (status == -1) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string interrupt_after_start(const std::string& command) {
    return command +
           " & pid=$!; for i in $(seq 600); do"
           " mask=$(awk '/^SigCgt/ {print $2}' /proc/$pid/status 2>/dev/null);"
           " [ -n \"$mask\" ] && [ $(( 0x$mask & 2 )) -ne 0 ] && break; sleep 0.1; done;"
           " sleep 1; kill -INT $pid; wait $pid";
}

std::string scene_xml(const std::string& body) { return "<scene version=\"3.0.0\">\n" + body + "\n</scene>\n"; }

const Mesh& load_single_mesh(const std::filesystem::path& dir, const std::string& shape_xml, Ref<Scene>& keep) {
    write_text(dir / "scene.xml", scene_xml(shape_xml));
    keep = load_scene((dir / "scene.xml").string());
    REQUIRE(keep->shapes().size() == 1);
    auto* mesh = dynamic_cast<const Mesh*>(keep->shapes()[0].get());
    REQUIRE(mesh != nullptr);
    return *mesh;
}

Ref<Scene> load_scene_xml(const std::string& name, const std::string& body) { return load_scene_xml_in(scratch_dir(name), body); }

Ref<Scene> load_scene_xml_in(const std::filesystem::path& dir, const std::string& body) {
    write_text(dir / "scene.xml", scene_xml(body));
    return load_scene((dir / "scene.xml").string());
}

std::string pinhole_camera(const std::string& origin, const std::string& target, int w, int h, float fov) {
    return "<sensor type=\"perspective\"><float name=\"fov\" value=\"" + std::to_string(fov) +
           "\"/><transform name=\"to_world\"><lookat origin=\"" + origin + "\" target=\"" + target +
           "\" up=\"0, 1, 0\"/></transform><film type=\"hdrfilm\"><integer name=\"width\" value=\"" + std::to_string(w) +
           "\"/><integer name=\"height\" value=\"" + std::to_string(h) +
           "\"/><rfilter type=\"box\"/></film><sampler type=\"independent\"/></sensor>";
}

std::string box_film(int size, int spp) {
    return R"(<film type="hdrfilm"><integer name="width" value=")" + std::to_string(size) + R"("/><integer name="height" value=")" +
           std::to_string(size) + R"("/><rfilter type="box"/><string name="component_format" value="float32"/></film>
        <sampler type="independent"><integer name="sample_count" value=")" +
           std::to_string(spp) + R"("/></sampler>)";
}

}  // namespace candela::test

namespace candela::test {

bool all_finite_pixels(const Image& image) {
    for (float v : image.data())
        if (!std::isfinite(v)) return false;
    return true;
}

RenderResult render_file(const std::string& scene_path, const SceneParameters& params, int threads, std::vector<std::string> aovs) {
    Ref<Scene> scene = load_scene(scene_path, params);
    RenderOptions options;
    options.threads = threads;
    options.aovs = std::move(aovs);
    return scene->integrator().render(*scene, options);
}

PixelView pixel_view(const Scene& scene, int x, int y) {
    const Vec2 origin = Vec2(scene.sensor().film().crop_offset()) + Vec2(float(x), float(y));
    PixelView view;
    bool first = true;
    for (Vec2 corner : {Vec2(1e-3f, 1e-3f), Vec2(0.999f, 1e-3f), Vec2(1e-3f, 0.999f), Vec2(0.999f, 0.999f)}) {
        SurfaceInteraction si;
        const Shape* hit = scene.intersect(scene.sensor().sample_ray(origin + corner, Vec2(0.5f)), si) ? si.shape : nullptr;
        if (first)
            view.shape = hit;
        else if (hit != view.shape)
            view.mixed = true;
        first = false;
    }
    if (view.mixed) view.shape = nullptr;
    return view;
}

}  // namespace candela::test
