#include "viewer/view_session.h"

#include "analysis/compare_modes.h"
#include "analysis/image_metrics.h"
#include "core/error.h"
#include "core/file_output.h"
#include "core/integrator.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "integrators/raster/raster.h"
#include "viewer/jpeg.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace candela {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// The methods a side can show, besides the integrators the registry offers.
const std::vector<std::string> ShorthandMethods = {"raster-gi", "baked"};
// Methods whose passes of sample ranges add up cheaply (no cache built per render call): the
// viewer refines them progressively; the others render whole, once per view.
const std::vector<std::string> ProgressiveMethods = {"path", "volpath", "volpathmis", "direct", "ao"};
// The sample count a progressive side refines towards (its passes are ranges of it).
constexpr int ProgressiveTarget = 1 << 16;

bool is_raster(const std::string& method) { return method == "raster" || method == "raster-gi" || method == "baked"; }
bool contains(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

Vec3 read_vec3(const json& j, const char* name) {
    const json& v = j.at(name);
    if (!v.is_array() || v.size() != 3) throw InputError(std::string(name) + " must be three numbers");
    Vec3 out;
    for (int i = 0; i < 3; ++i) {
        if (!v[size_t(i)].is_number()) throw InputError(std::string(name) + " must be three numbers");
        out[i] = v[size_t(i)].get<float>();
    }
    if (!all_finite(out) || max_abs_component(out) > 1e7f) throw InputError(std::string(name) + " must be finite and within 1e7");
    return out;
}

json vec3_json(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

// The film channels of a developed image (R, G, B[, A]): what `candela render` writes.
Image film_channels(const Image& developed) {
    std::vector<int> keep;
    std::vector<std::string> names;
    for (int c = 0; c < developed.channel_count(); ++c)
        if (developed.channels()[size_t(c)].find('.') == std::string::npos) {
            keep.push_back(c);
            names.push_back(developed.channels()[size_t(c)]);
        }
    Image out(developed.width(), developed.height(), names);
    for (int y = 0; y < developed.height(); ++y)
        for (int x = 0; x < developed.width(); ++x)
            for (size_t k = 0; k < keep.size(); ++k) out.at(x, y, int(k)) = developed.at(x, y, keep[k]);
    out.metadata = developed.metadata;
    return out;
}

}  // namespace

struct ViewSession::Side {
    int index = 0;
    std::string method;
    Ref<Integrator> integrator;  // null: the scene's own
    std::string integrator_key;  // the method and settings it was built for: kept while they stay (the raster mode caches its geometry)
    bool progressive = false, raster = false;
    uint64_t generation = 0;  // of the image it holds (0: none)
    uint32_t camera_id = 0;
    bool done = false;
    bool fresh = false;  // holds what the pages have not seen
    // Progressive accumulation.
    PixelSums sums;
    int spp_done = 0;
    double seconds = 0.0;
    uint64_t samples = 0, rays = 0;
    Clock::time_point started;
    RenderStats pass_stats;  // the last pass's (sampler, seed), for the saved file's metadata
    // What the pages see (guarded by the session's mutex): the linear image and, for saving,
    // the developed film with its statistics.
    Image image, film;
    RenderStats stats;
};

ViewSession::ViewSession(Ref<Scene> scene, std::string scene_path, ViewSink sink)
    : scene_(std::move(scene)), scene_path_(std::move(scene_path)), sink_(std::move(sink)) {
    methods_ = {"path", "raster"};
    for (const std::string& m : ShorthandMethods) methods_.push_back(m);
    for (const std::string& name : plugin_names(ObjectKind::Integrator))
        if (!contains(methods_, name) && name != "aov" && name != "moment" && name != "irradiance") methods_.push_back(name);
    // The camera the scene starts with, looking at the middle of the scene.
    const Sensor& sensor = scene_->sensor();
    const Transform& t = sensor.to_world();
    camera_.origin = t.apply_point(Vec3(0.0f));
    const Vec3 forward = glm::normalize(t.apply_vector(Vec3(0.0f, 0.0f, 1.0f)));
    const BoundingBox& b = scene_->bbox();
    float distance = b.valid() ? glm::dot(b.center() - camera_.origin, forward) : 1.0f;
    if (!(distance > 1e-3f)) distance = b.valid() ? std::max(b.bounding_radius(), 1e-3f) : 1.0f;
    camera_.target = camera_.origin + forward * distance;
    camera_.up = glm::normalize(t.apply_vector(Vec3(0.0f, 1.0f, 0.0f)));
    if (auto p = sensor.pinhole()) camera_.fov = degrees(2.0f * std::atan(p->tan_half_x));
    for (int i = 0; i < 2; ++i) {
        auto side = std::make_unique<Side>();
        side->index = i;
        sides_.push_back(std::move(side));
    }
    thread_ = std::thread([this] { run(); });
    publisher_ = std::thread([this] { run_publisher(); });
}

ViewSession::~ViewSession() { stop(); }

void ViewSession::set_viewers(int count) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        viewers_ = count;
        if (count == 0) restart_ = true;  // the running pass stops; the side resumes it later
    }
    wake_.notify_all();
}

void ViewSession::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
        restart_ = true;
    }
    wake_.notify_all();
    publish_wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    if (publisher_.joinable()) publisher_.join();
}

std::string ViewSession::settings_json() const {
    const ViewSettings& s = settings_;
    return json{{"left", s.left},       {"right", s.right},     {"shading", s.shading}, {"reflection", s.reflection},
                {"shadows", s.shadows}, {"aa", s.aa},           {"gi", s.gi},           {"exposure", s.exposure},
                {"tonemap", s.tonemap}, {"heatmap", s.heatmap}, {"split", s.split}}
        .dump();
}

std::string ViewSession::hello_json() const {
    std::lock_guard<std::mutex> lock(mutex_);
    const Vec2i size = scene_->sensor().film().crop_size();
    const BoundingBox& b = scene_->bbox();
    json j = {{"type", "scene"},
              {"width", size.x},
              {"height", size.y},
              {"camera",
               {{"origin", vec3_json(camera_.origin)},
                {"target", vec3_json(camera_.target)},
                {"up", vec3_json(camera_.up)},
                {"fov", camera_.fov},
                {"id", camera_.id}}},
              {"bbox", {{"min", vec3_json(b.valid() ? b.min : Vec3(0.0f))}, {"max", vec3_json(b.valid() ? b.max : Vec3(0.0f))}}},
              {"methods", methods_},
              {"settings", json::parse(settings_json())}};
    return j.dump();
}

std::string ViewSession::apply_message(uint64_t page, const std::string& text, std::string& broadcast) {
    auto error = [](const std::string& message) { return json{{"type", "error"}, {"message", message}}.dump(); };
    json message;
    try {
        message = json::parse(text);
    } catch (const std::exception&) {
        return error("not JSON");
    }
    if (!message.is_object() || !message.contains("type") || !message["type"].is_string())
        return error("a message is an object with a \"type\"");
    const std::string type = message["type"].get<std::string>();
    try {
        if (type == "hello") {
            // A new page gets the current images too (they are sent to every page).
            {
                std::lock_guard<std::mutex> lock(mutex_);
                redisplay_ = true;
            }
            publish_wake_.notify_all();
            return hello_json();
        }
        if (type == "ping") {
            if (!message.contains("id") || !message["id"].is_number()) return error("ping needs a numeric id");
            return json{{"type", "pong"}, {"id", message["id"]}}.dump();
        }
        if (type == "camera") {
            ViewCamera c;
            c.origin = read_vec3(message, "origin");
            c.target = read_vec3(message, "target");
            c.up = read_vec3(message, "up");
            if (!message.contains("fov") || !message["fov"].is_number()) throw InputError("fov must be a number");
            c.fov = message["fov"].get<float>();
            if (!(c.fov > 0.1f && c.fov < 179.0f)) throw InputError("fov must lie between 0.1 and 179 degrees");
            const Vec3 d = c.target - c.origin;
            if (!(glm::length(d) > 1e-6f)) throw InputError("origin and target coincide");
            if (!(glm::length(glm::cross(glm::normalize(d), c.up)) > 1e-6f)) throw InputError("up is parallel to the view direction");
            if (message.contains("id")) {
                if (!message["id"].is_number_unsigned()) throw InputError("id must be a whole number");
                c.id = uint32_t(std::min<uint64_t>(message["id"].get<uint64_t>(), UINT32_MAX));
            }
            {
                std::lock_guard<std::mutex> lock(mutex_);
                camera_ = c;
                ++generation_;
                restart_ = true;
            }
            wake_.notify_all();
            json echo = message;
            broadcast = echo.dump();
            return "";
        }
        if (type == "settings") {
            ViewSettings s;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                s = settings_;
            }
            bool images = false, display = false;
            auto choice = [&](const char* key, std::string& field, const std::vector<std::string>& allowed, bool changes_images) {
                if (!message.contains(key)) return;
                if (!message[key].is_string() || !contains(allowed, message[key].get<std::string>()))
                    throw InputError(std::string(key) + " must be one of the accepted values");
                if (field != message[key].get<std::string>()) images = images || changes_images;
                field = message[key].get<std::string>();
            };
            choice("left", s.left, methods_, true);
            choice("right", s.right, methods_, true);
            choice("shading", s.shading, {"flat", "gouraud", "phong"}, true);
            choice("reflection", s.reflection, {"phong", "blinn"}, true);
            choice("shadows", s.shadows, {"none", "map", "volume"}, true);
            choice("gi", s.gi, {"none", "ao", "ibl", "baked-radiosity", "baked-path"}, true);
            if (message.contains("tonemap")) {
                const std::string before = s.tonemap;
                choice("tonemap", s.tonemap, {"srgb", "filmic"}, false);
                display = display || before != s.tonemap;
            }
            if (message.contains("aa")) {
                if (!message["aa"].is_number_integer() || message["aa"].get<int64_t>() < 1 || message["aa"].get<int64_t>() > 16)
                    throw InputError("aa must be a whole number from 1 to 16");
                images = images || s.aa != message["aa"].get<int>();
                s.aa = message["aa"].get<int>();
            }
            if (message.contains("exposure")) {
                if (!message["exposure"].is_number() || !(std::fabs(message["exposure"].get<double>()) <= 10.0))
                    throw InputError("exposure must be a number from -10 to 10");
                display = display || s.exposure != message["exposure"].get<float>();
                s.exposure = message["exposure"].get<float>();
            }
            if (message.contains("heatmap")) {
                if (!message["heatmap"].is_boolean()) throw InputError("heatmap must be true or false");
                display = display || s.heatmap != message["heatmap"].get<bool>();
                s.heatmap = message["heatmap"].get<bool>();
            }
            if (message.contains("split")) {
                if (!message["split"].is_number() || !(message["split"].get<double>() >= 0.0 && message["split"].get<double>() <= 1.0))
                    throw InputError("split must lie between 0 and 1");
                s.split = message["split"].get<float>();
            }
            {
                std::lock_guard<std::mutex> lock(mutex_);
                settings_ = s;
                if (images) {
                    ++generation_;
                    restart_ = true;
                }
                redisplay_ = redisplay_ || display;
            }
            wake_.notify_all();
            publish_wake_.notify_all();
            std::lock_guard<std::mutex> lock(mutex_);
            broadcast = json{{"type", "settings"}, {"settings", json::parse(settings_json())}}.dump();
            return "";
        }
        if (type == "inspect") {
            if (!message.contains("x") || !message.contains("y") || !message["x"].is_number() || !message["y"].is_number())
                throw InputError("inspect needs x and y");
            const double fx = message["x"].get<double>(), fy = message["y"].get<double>();
            const std::string side_name =
                message.contains("side") && message["side"].is_string() ? message["side"].get<std::string>() : "left";
            if (side_name != "left" && side_name != "right") throw InputError("side must be left or right");
            const Vec2i size = scene_->sensor().film().crop_size();
            if (!(fx >= 0.0 && fy >= 0.0 && fx < size.x && fy < size.y)) throw InputError("x, y lie outside the image");
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (inspections_.size() >= 64) throw InputError("too many inspections waiting");
                inspections_.push_back(Inspection{page, side_name == "left" ? 0 : 1, int(fx), int(fy)});
                restart_ = true;  // the running render yields at its next tile; the side resumes after the answer
            }
            wake_.notify_all();
            return "";  // the render thread answers (inspect)
        }
        return error("unknown message type \"" + type + "\"");
    } catch (const nlohmann::json::exception& e) {
        return error(std::string("malformed ") + type + " message");
    } catch (const InputError& e) {
        return error(e.what());
    }
}

Ref<Integrator> ViewSession::make_method(const std::string& method) const {
    const ViewSettings s = settings_;
    auto adjust = [&](RasterSettings& r) {
        std::string problem;
        r.set("shading", s.shading, problem);
        r.set("reflection", s.reflection, problem);
        r.set("shadows", s.shadows, problem);
        r.aa = s.aa;
        if (method != "raster") return;
        if (s.gi == "ao") r.ao = 16;
        if (s.gi == "ibl") r.set("environment_lighting", "ibl", problem);
        if (s.gi == "none" || s.gi == "ao") r.set("environment_lighting", "average", problem);
        if (s.gi == "baked-radiosity" || s.gi == "baked-path") {
            r.set("lighting", "baked", problem);
            r.set("bake", s.gi == "baked-path" ? "path" : "radiosity", problem);
            r.bake_samples = 64;
        }
    };
    return method_integrator(method, *scene_, adjust);
}

void ViewSession::apply_camera_to_scene(const ViewCamera& camera) {
    Sensor& sensor = scene_->sensor();
    const Transform to_world = Transform::look_at(camera.origin, camera.target, camera.up);
    std::vector<const SceneParameter*> changed;
    std::vector<SceneParameter> all = scene_parameters(*scene_);
    for (const SceneParameter& p : all) {
        if (p.owner != &sensor) continue;
        if (p.key == "to_world") {
            std::vector<float> v(16);
            const Mat4& m = to_world.matrix();
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) v[size_t(r * 4 + c)] = m[c][r];
            p.access.set(v);
            changed.push_back(&p);
        } else if (p.key == "x_fov") {
            p.access.set({camera.fov});
            changed.push_back(&p);
        }
    }
    apply_parameter_changes(*scene_, changed);
}

void ViewSession::publish_frame(int kind, const Image& image, uint32_t camera_id, bool display) {
    if (image.width() == 0 || !sink_.frame) return;
    ViewSettings s;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        s = settings_;
    }
    std::string frame(9, '\0');
    frame[0] = char(kind);
    const uint32_t seq = ++sequence_;
    std::memcpy(&frame[1], &seq, 4);
    std::memcpy(&frame[5], &camera_id, 4);
    frame += display ? encode_jpeg(image, JpegTone::Display, 0.0f)
                     : encode_jpeg(image, s.tonemap == "filmic" ? JpegTone::Filmic : JpegTone::Srgb, s.exposure);
    sink_.frame(frame);
}

void ViewSession::send_status() {
    json status = {{"type", "status"}};
    Image a, b;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& side : sides_) {
            const double sps = side->seconds > 0.0 ? double(side->samples) / side->seconds : 0.0;
            status[side->index == 0 ? "left" : "right"] = {{"method", side->method},
                                                           {"spp", side->progressive ? side->spp_done : side->stats.spp},
                                                           {"seconds", side->seconds},
                                                           {"samples_per_second", sps},
                                                           {"done", side->done}};
        }
        status["generation"] = generation_;
        a = sides_[0]->image;
        b = sides_[1]->image;
    }
    status["relmse"] = nullptr;
    status["block_mare"] = nullptr;
    if (a.width() > 0 && b.width() > 0 && a.width() == b.width() && a.height() == b.height()) {
        const ImageComparison c = compare_images(a, b);
        status["relmse"] = c.relmse;
        status["block_mare"] = c.block_mare;
    }
    if (sink_.text) sink_.text(status.dump());
}

double ViewSession::samples_per_second(int index) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const Side& side = *sides_[size_t(index)];
    return side.seconds > 0.0 ? double(side.samples) / side.seconds : 0.0;
}

void ViewSession::render_side(Side& side, uint64_t generation) {
    const auto start = Clock::now();
    RenderOptions options;
    options.interrupt = &restart_;
    Integrator& integrator = side.integrator ? *side.integrator : scene_->integrator();
    if (side.raster) {
        // A raster frame is kept even when the camera moved on while it was drawn: it is the
        // newest view there is, and the next one follows within a frame.
        RenderResult r = integrator.render(*scene_, options);
        std::lock_guard<std::mutex> lock(mutex_);
        side.image = linear_rgb(r.image);
        side.stats = r.stats;
        side.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        side.done = true;
        return;
    }
    if (!side.progressive) {
        RenderResult r = integrator.render(*scene_, options);
        if (restart_ || r.stats.partial) return;
        annotate_image(r.image, r.stats, integrator.to_string(), scene_path_);
        std::lock_guard<std::mutex> lock(mutex_);
        if (generation_ != generation) return;
        side.film = film_channels(r.image);
        side.image = linear_rgb(side.film);
        side.stats = r.stats;
        side.samples = r.stats.samples;
        side.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        side.done = side.fresh = true;
        return;
    }
    // One render call for the rest of the sample indices, in passes narrow enough (about 0.05 to
    // 0.2 s) for a checkpoint after each: the checkpoint hands the sums so far to the publisher,
    // which develops them about five times a second. One call instead of a call per pass saves
    // the set-up and final gathering of every pass (issue 30's samples-per-second goal). A camera
    // move, an inspection or the last page leaving interrupts it; what the last checkpoint
    // handed over stays, and the side resumes from there.
    const PixelSums base = side.sums;  // the samples [0, spp_done) of earlier calls
    const int first = side.spp_done;
    const Vec2i size = scene_->sensor().film().crop_size();
    const uint64_t pixels = uint64_t(size.x) * uint64_t(size.y);
    options.spp = ProgressiveTarget;
    options.samples = SampleRange{first, ProgressiveTarget};
    options.widest_pass = int(std::clamp<uint64_t>((uint64_t(1) << 18) / std::max<uint64_t>(pixels, 1), 1, 32));
    options.checkpoint_seconds = 0.15;
    // Takes the sums of this call's samples [first, end) (under the lock).
    auto take = [&](const PixelSums& running, int end) {
        if (first == 0) {
            side.sums = running;
        } else {
            side.sums = base;
            side.sums.add(running);
        }
        side.samples += uint64_t(end - side.spp_done) * pixels;
        side.spp_done = end;
        // Wall time since the side started this view: its samples per second include everything
        // the viewer does besides rendering (developing, encoding, the other side).
        side.seconds = std::chrono::duration<double>(Clock::now() - side.started).count();
        side.fresh = true;
        publish_wake_.notify_all();
    };
    options.checkpoint = [&](const PixelSums& running, const std::vector<CoverageBox>& coverage) {
        // Between passes every tile holds the same samples [first, end).
        if (coverage.size() != 1) return;
        const int end = coverage[0].samples.end;
        std::lock_guard<std::mutex> lock(mutex_);
        if (generation_ != generation || end <= side.spp_done) return;
        take(running, end);
    };
    if (side.pass_stats.sampler.empty()) {
        // The saved file's metadata before the first call returns: the sampler and seed it uses.
        Ref<Sampler> sampler = configured_sampler(*scene_, options);
        side.pass_stats.sampler = sampler->to_string();
        side.pass_stats.seed = sampler->seed();
    }
    RenderResult r = integrator.render(*scene_, options);
    if (restart_ || r.stats.partial) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (generation_ != generation) return;
    take(r.sums, ProgressiveTarget);
    side.rays += r.stats.rays;
    side.pass_stats = r.stats;
    side.done = true;
}

void ViewSession::inspect(const Inspection& request) {
    json reply = {{"type", "pixel"}, {"side", request.side == 0 ? "left" : "right"}, {"x", request.x}, {"y", request.y}};
    Spectrum radiance(0.0f), ci(0.0f);
    int spp = 0;
    bool progressive = false;
    Integrator* integrator = nullptr;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        Side& side = *sides_[size_t(request.side)];
        if (side.image.width() == 0) {
            if (sink_.reply) sink_.reply(request.page, json{{"type", "error"}, {"message", "that side has no image yet"}}.dump());
            return;
        }
        radiance = side.image.rgb_at(request.x, request.y);
        progressive = side.progressive;
        spp = progressive ? side.spp_done : side.stats.spp;
        integrator = side.integrator ? side.integrator.get() : &scene_->integrator();
    }
    // The pixel's own samples again (the same indices the image holds, at most 4096), with their
    // moments: a 95% interval of its mean, 1.96 sqrt(variance / n).
    if (progressive && spp > 1) {
        RenderOptions options;
        options.spp = ProgressiveTarget;
        options.samples = SampleRange{0, std::min(spp, 4096)};
        options.region = ImageRect{Vec2i(request.x, request.y), Vec2i(1)};
        options.aovs = {"variance"};
        options.threads = 1;
        const RenderResult r = integrator->render(*scene_, options);
        const Vec2i at = Vec2i(request.x, request.y) - r.sums.rect().offset;
        if (r.sums.has_stats()) {
            const PixelStats& ps = r.sums.stats_at(at.x, at.y);
            if (ps.n > 1)
                for (int c = 0; c < 3; ++c) {
                    const double n = ps.n, mean = ps.sum[c] / n;
                    ci[c] = float(1.96 * std::sqrt(std::max(0.0, (ps.sum_sq[c] - n * mean * mean) / (n - 1.0)) / n));
                }
        }
    }
    reply["radiance"] = vec3_json(radiance);
    reply["ci95"] = vec3_json(ci);
    reply["spp"] = spp;
    if (sink_.reply) sink_.reply(request.page, reply.dump());
}

void ViewSession::run() {
    ViewCamera applied;
    applied.id = UINT32_MAX;
    for (;;) {
        ViewCamera camera;
        ViewSettings settings;
        uint64_t generation;
        std::vector<Inspection> inspections;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            auto has_work = [&] {
                if (stopping_ || !inspections_.empty()) return true;
                if (viewers_ == 0) return false;
                for (const auto& side : sides_)
                    if (side->generation != generation_ || !side->done) return true;
                return false;
            };
            wake_.wait_for(lock, std::chrono::milliseconds(250), has_work);
            if (stopping_) return;
            inspections.swap(inspections_);
            camera = camera_;
            settings = settings_;
            generation = generation_;
            restart_ = false;
            if (viewers_ == 0 && inspections.empty()) continue;
        }
        try {
            if (camera.origin != applied.origin || camera.target != applied.target || camera.up != applied.up ||
                camera.fov != applied.fov) {
                apply_camera_to_scene(camera);
                applied = camera;
            }
            // A side whose image is of an older view starts again (its method rebuilt when it changed).
            for (auto& side : sides_) {
                const std::string method = side->index == 0 ? settings.left : settings.right;
                if (side->generation == generation) continue;
                const std::string key = method + "|" + settings.shading + "|" + settings.reflection + "|" + settings.shadows + "|" +
                                        settings.gi + "|" + std::to_string(settings.aa);
                Ref<Integrator> integrator = side->integrator;
                if (key != side->integrator_key || side->method != method) integrator = make_method(method);
                std::lock_guard<std::mutex> lock(mutex_);
                side->method = method;
                side->integrator = integrator;
                side->integrator_key = key;
                side->raster = is_raster(method);
                side->progressive = !side->raster && contains(ProgressiveMethods, method);
                side->generation = generation;
                side->camera_id = camera.id;
                side->done = side->fresh = false;
                side->spp_done = 0;
                side->seconds = 0.0;
                side->started = Clock::now();
                side->samples = side->rays = 0;
                side->sums = PixelSums();
            }
            for (const Inspection& request : inspections) inspect(request);
            // Raster first, sent at once: it answers a camera move within a frame.
            for (auto& side : sides_)
                if (side->raster && !side->done) {
                    render_side(*side, generation);
                    Image image;
                    {
                        std::lock_guard<std::mutex> lock(mutex_);
                        image = side->image;
                    }
                    publish_frame(side->index, image, side->camera_id, false);
                    {
                        std::lock_guard<std::mutex> lock(mutex_);
                        heatmap_due_ = true;
                    }
                    publish_wake_.notify_all();  // the heatmap and the status follow
                }
            if (restart_) continue;
            for (auto& side : sides_)
                if (!side->raster && !side->done) {
                    render_side(*side, generation);
                    if (restart_) break;
                }
        } catch (const std::exception& e) {
            if (sink_.text) sink_.text(json{{"type", "error"}, {"message", e.what()}}.dump());
            std::lock_guard<std::mutex> lock(mutex_);
            for (auto& side : sides_) side->done = true;  // nothing more to do until the next change
        }
    }
}

void ViewSession::run_publisher() {
    auto last_status = Clock::now(), last_publish = Clock::now() - std::chrono::seconds(1);
    for (;;) {
        bool redisplay, heatmap_due;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            // Woken by what is new, but at most five images a second of a refining side.
            auto fresh = [&] {
                for (const auto& side : sides_)
                    if (side->fresh) return true;
                return false;
            };
            publish_wake_.wait_for(lock, std::chrono::milliseconds(200),
                                   [&] { return stopping_ || redisplay_ || heatmap_due_ || fresh(); });
            if (stopping_) return;
            const double since = std::chrono::duration<double>(Clock::now() - last_publish).count();
            if (!redisplay_ && !heatmap_due_ && since < 0.2) {
                lock.unlock();
                std::this_thread::sleep_for(std::chrono::duration<double>(0.2 - since));
                lock.lock();
                if (stopping_) return;
            }
            if (viewers_ == 0) continue;
            redisplay = redisplay_;
            redisplay_ = false;
            heatmap_due = heatmap_due_;
            heatmap_due_ = false;
        }
        bool published = false;
        try {
            for (auto& side_ptr : sides_) {
                Side& side = *side_ptr;
                PixelSums sums;
                RenderStats stats;
                Image image;
                uint32_t camera_id;
                bool develop = false;
                {
                    std::lock_guard<std::mutex> lock(mutex_);
                    if (!(side.fresh || (redisplay && side.image.width() > 0))) continue;
                    develop = side.fresh && side.progressive;
                    if (develop) {
                        sums = side.sums;  // a copy: the render thread goes on adding passes
                        stats = side.pass_stats;
                        stats.seconds = side.seconds;
                        stats.samples = side.samples;
                        stats.rays = side.rays;
                        stats.spp = side.spp_done;
                        stats.partial = false;
                    }
                    side.fresh = false;
                    image = side.image;
                    camera_id = side.camera_id;
                }
                if (develop) {
                    Image developed = sums.develop();
                    annotate_image(developed, stats, side.integrator ? side.integrator->to_string() : scene_->integrator().to_string(),
                                   scene_path_);
                    Image film = film_channels(developed);
                    image = linear_rgb(film);
                    std::lock_guard<std::mutex> lock(mutex_);
                    if (side.camera_id != camera_id) continue;  // a newer view began meanwhile
                    side.film = std::move(film);
                    side.image = image;
                    side.stats = stats;
                }
                publish_frame(side.index, image, camera_id, false);
                published = true;
                last_publish = Clock::now();
            }
            bool heatmap;
            Image a, b;
            uint32_t camera_id;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                heatmap = settings_.heatmap;
                a = sides_[0]->image;
                b = sides_[1]->image;
                camera_id = std::max(sides_[0]->camera_id, sides_[1]->camera_id);
            }
            if (heatmap && (published || redisplay || heatmap_due) && a.width() > 0 && a.width() == b.width() && a.height() == b.height())
                publish_frame(2, relative_difference_map(a, b, 0.5f), camera_id, true);
            if (published || std::chrono::duration<double>(Clock::now() - last_status).count() >= 0.25) {
                send_status();
                last_status = Clock::now();
            }
        } catch (const std::exception& e) {
            if (sink_.text) sink_.text(json{{"type", "error"}, {"message", e.what()}}.dump());
        }
    }
}

std::optional<std::string> ViewSession::save_exr(const std::string& side_name) {
    if (side_name != "left" && side_name != "right") throw InputError("side must be left or right");
    Image film;
    bool float32 = scene_->sensor().film().float32();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        film = sides_[side_name == "left" ? 0 : 1]->film;
    }
    if (film.width() == 0) return std::nullopt;
    char name[] = "/tmp/candela-view-XXXXXX.exr";
    const int fd = mkstemps(name, 4);
    if (fd < 0) throw InputError("cannot create a temporary file");
    ::close(fd);
    std::filesystem::remove(name);
    std::string bytes;
    try {
        write_exr(film, name, float32);
        std::ifstream in(name, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    } catch (...) {
        std::filesystem::remove(name);
        throw;
    }
    std::filesystem::remove(name);
    return bytes;
}

}  // namespace candela
