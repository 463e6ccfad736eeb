#include "tests/util.h"

#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace candela::test {

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

int run_command(const std::string& command, const std::filesystem::path& log) {
    std::string full = "{ " + command + " ; } > '" + log.string() + "' 2>&1";
    int status = std::system(full.c_str());
    if (status == -1) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string scene_xml(const std::string& body) { return "<scene version=\"3.0.0\">\n" + body + "\n</scene>\n"; }

Ref<Scene> load_scene_xml(const std::string& name, const std::string& body) {
    auto dir = scratch_dir(name);
    write_text(dir / "scene.xml", scene_xml(body));
    return load_scene((dir / "scene.xml").string());
}

std::string pinhole_camera(const std::string& origin, const std::string& target, int w, int h, float fov) {
    return "<sensor type=\"perspective\"><float name=\"fov\" value=\"" + std::to_string(fov) + "\"/><transform name=\"to_world\"><lookat origin=\"" + origin +
           "\" target=\"" + target + "\" up=\"0, 1, 0\"/></transform><film type=\"hdrfilm\"><integer name=\"width\" value=\"" + std::to_string(w) +
           "\"/><integer name=\"height\" value=\"" + std::to_string(h) + "\"/><rfilter type=\"box\"/></film></sensor>";
}

}  // namespace candela::test

namespace candela::test {

RenderResult render_file(const std::string& scene_path, const SceneParameters& params, int threads, std::vector<std::string> aovs) {
    Ref<Scene> scene = load_scene(scene_path, params);
    RenderOptions options;
    options.threads = threads;
    options.aovs = std::move(aovs);
    return scene->integrator().render(*scene, options);
}

}  // namespace candela::test
