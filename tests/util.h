#pragma once
// Helpers shared by the tests: scratch directories, small files, and scene snippets.

#include "core/image_codecs.h"
#include "core/integrator.h"
#include "core/mesh.h"
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

// The image module's codecs (core/image_codecs.h), loaded as core/image.cpp loads it: what the
// readers that go around it (core/exr_input.h, core/png_file.h) must give.
const ImageCodecs& module_codecs();

// Runs a shell command; returns its exit code (not the raw wait status). Output goes to `log`.
int run_command(const std::string& command, const std::filesystem::path& log);
// A shell line that starts `command` in the background and, once its SIGINT handler is
// installed (SigCgt in /proc/PID/status has SIGINT's bit) and a second later, sends it SIGINT
// and waits. A background job of a non-interactive shell starts with SIGINT ignored, so a signal
// sent before the handler is installed would be lost and the command would run to its end.
std::string interrupt_after_start(const std::string& command);
std::string read_text(const std::filesystem::path& path);

// Loads a scene file with `params` and renders it with its own integrator.
RenderResult render_file(const std::string& scene_path, const SceneParameters& params, int threads = 0, std::vector<std::string> aovs = {});
// Whether every value of every pixel and channel is finite.
bool all_finite_pixels(const Image& image);

// CANDELA_TEST_EFFORT: a number in (0, 1], default 1. The sanitizer runs of scripts/test.sh set
// it to run the long tests at reduced size.
double test_effort();
// A statistical test's sample count scaled by test_effort(), never below `minimum`. Their significance stays as stated: thresholds come from
// the estimator's own variance and the Sidak correction, which hold at any sample count; what a
// smaller count loses is power (larger errors go unseen), not honesty. Tests that assert a power
// or a fixed tolerance must not use it.
int effort_scaled(int samples, int minimum);

// A minimal scene document around `body` (sensor, film and integrator given by the caller).
std::string scene_xml(const std::string& body);
// That document written to a fresh scratch directory `name` as scene.xml, and loaded.
Ref<Scene> load_scene_xml(const std::string& name, const std::string& body);
// That document written to `dir` (beside the files it reads) as scene.xml, and loaded.
Ref<Scene> load_scene_xml_in(const std::filesystem::path& dir, const std::string& body);
// The scene of one mesh shape (`shape_xml`) written to `dir` as scene.xml and loaded into `keep`:
// its mesh (REQUIREd to be the scene's only shape, and a mesh).
const Mesh& load_single_mesh(const std::filesystem::path& dir, const std::string& shape_xml, Ref<Scene>& keep);
// A perspective sensor at `origin` looking at `target` (up +y, fov in degrees along x) with a
// box-filtered w x h film, as XML.
std::string pinhole_camera(const std::string& origin, const std::string& target, int w, int h, float fov = 60);
// A size x size float32 hdrfilm with a box filter and an independent sampler of `spp`, as XML
// (inside a <sensor>).
std::string box_film(int size, int spp);

// What the camera sees over the whole of pixel (x, y) of the crop window, judged by the camera
// rays through its four corners (right for convex shapes with nothing in front): the shape all
// four hit first, or nothing when all four miss; `mixed` when they disagree.
struct PixelView {
    const Shape* shape = nullptr;
    bool mixed = false;
    bool nothing() const { return !shape && !mixed; }
};
PixelView pixel_view(const Scene& scene, int x, int y);

}  // namespace candela::test
