#pragma once
// Helpers shared by the tests: scratch directories, small files, and scene snippets.

#include "core/integrator.h"
#include "core/xml.h"

#include <filesystem>
#include <string>
#include <vector>

namespace candela::test {

// A fresh directory under the build tree for this test's files (one per process).
std::filesystem::path scratch_dir(const std::string& name);
void write_text(const std::filesystem::path& path, const std::string& text);
std::string source_path(const std::string& relative);  // inside the repository
std::string candela_binary();

// Runs a shell command; returns its exit code (not the raw wait status). Output goes to `log`.
int run_command(const std::string& command, const std::filesystem::path& log);
std::string read_text(const std::filesystem::path& path);

// Loads a scene file with `params` and renders it with its own integrator.
RenderResult render_file(const std::string& scene_path, const SceneParameters& params, int threads = 0, std::vector<std::string> aovs = {});

// A minimal scene document around `body` (sensor, film and integrator given by the caller).
std::string scene_xml(const std::string& body);
// That document written to a fresh scratch directory `name` as scene.xml, and loaded.
Ref<Scene> load_scene_xml(const std::string& name, const std::string& body);
// A perspective sensor at `origin` looking at `target` (up +y, fov in degrees along x) with a
// box-filtered w x h film, as XML.
std::string pinhole_camera(const std::string& origin, const std::string& target, int w, int h, float fov = 60);

}  // namespace candela::test
