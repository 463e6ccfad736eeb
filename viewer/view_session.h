#pragma once
// What `candela view` shows: one scene, one camera and one set of settings shared by every page,
// rendered by two methods side by side (left and right: the progressive path tracer, the raster
// mode in real time, or another method of compare-modes) on a thread of its own. Pages change
// the camera and the settings (apply_message); the session renders what changed and hands
// frames (JPEG) and status (JSON) to a sink, which the server broadcasts to the pages.
//
// The raster side is rendered first whenever the camera moved and sent at once; the progressive
// side restarts at once and renders passes of growing sample ranges of the scene's sampler (no
// AOVs: nothing but the image is paid for), each interrupted as soon as the camera or the
// settings change again, while a publisher thread sends its image about five times a second.

#include "core/image.h"
#include "core/pixel_sums.h"
#include "core/scene.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace candela {

class Integrator;

struct ViewCamera {
    Vec3 origin{0.0f}, target{0.0f, 0.0f, 1.0f}, up{0.0f, 1.0f, 0.0f};
    float fov = 45.0f;  // degrees along x
    uint32_t id = 0;    // the page's message id, echoed in frames
};

struct ViewSettings {
    std::string left = "path", right = "raster";
    std::string shading = "phong", reflection = "blinn", shadows = "map", gi = "none", tonemap = "srgb";
    int aa = 1;
    float exposure = 0.0f;  // EV
    bool heatmap = false;
    float split = 0.5f;
};

// Where the session sends what it renders: frames (byte 0: 0 left, 1 right, 2 heatmap; then
// uint32 sequence and camera id, little-endian; then JPEG) and JSON text to every page, and
// answers to one page (`reply`, by the id the server gave the page's message).
struct ViewSink {
    std::function<void(const std::string& bytes)> frame;
    std::function<void(const std::string& json)> text;
    std::function<void(uint64_t page, const std::string& json)> reply;
};

class ViewSession {
public:
    // Loads nothing itself: the scene is loaded (and checked) by the caller.
    ViewSession(Ref<Scene> scene, std::string scene_path, ViewSink sink);
    ~ViewSession();
    ViewSession(const ViewSession&) = delete;
    ViewSession& operator=(const ViewSession&) = delete;

    // The "scene" message a page gets on hello: size, camera, bounds, methods, settings.
    std::string hello_json() const;
    // Applies one message from page `page` ("camera", "settings", "inspect", "ping"); returns
    // the reply for that page ("" for none; an inspection answers later through sink.reply). A
    // malformed or refused message changes nothing and gets an {"type":"error"} reply.
    // `broadcast` receives what the other pages must learn (a camera or settings change).
    std::string apply_message(uint64_t page, const std::string& text, std::string& broadcast);
    // The current accumulation of a side as an OpenEXR file's bytes (what `candela render`
    // writes for that spp, metadata included), or nothing when there is none.
    std::optional<std::string> save_exr(const std::string& side);

    // Stops the render thread (pages are served by the server).
    void stop();
    // How many pages are connected: without one, nothing is rendered (the machine stays idle).
    void set_viewers(int count);

    // Figures for benchmarks and tests: samples per second of the progressive sides so far.
    double samples_per_second(int side) const;

private:
    struct Side;
    struct Inspection {
        uint64_t page;
        int side, x, y;
    };
    // The render thread: renders what the views need, answers inspections.
    void run();
    void render_side(Side& side, uint64_t generation);
    void inspect(const Inspection& request);
    // The publisher thread: about five times a second, develops and sends what changed, and the
    // status; the raster frames go out from the render thread at once.
    void run_publisher();
    void publish_frame(int kind, const Image& image, uint32_t camera_id, bool display);
    void send_status();
    void apply_camera_to_scene(const ViewCamera& camera);
    Ref<Integrator> make_method(const std::string& method) const;
    std::string settings_json() const;

    Ref<Scene> scene_;
    std::string scene_path_;
    ViewSink sink_;
    std::vector<std::string> methods_;

    mutable std::mutex mutex_;  // guards the fields below and the sides' published results
    std::condition_variable wake_;
    ViewCamera camera_;
    ViewSettings settings_;
    uint64_t generation_ = 1;   // changes with every change of the camera or the settings that changes images
    bool redisplay_ = false;    // send the current images again (exposure or tonemap changed, a page said hello)
    bool heatmap_due_ = false;  // a raster frame went out: the heatmap follows
    bool stopping_ = false;
    int viewers_ = 0;
    std::atomic<bool> restart_{false};  // set when the generation changes: interrupts the running render
    std::vector<std::unique_ptr<Side>> sides_;
    std::vector<Inspection> inspections_;
    std::atomic<uint32_t> sequence_{0};
    std::condition_variable publish_wake_;
    std::thread thread_, publisher_;
};

}  // namespace candela
