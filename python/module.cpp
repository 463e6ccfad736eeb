// candela._candela: the native half of the Python package (python/candela/). It loads scenes,
// renders them with the GIL released, holds images that NumPy views without a copy (the buffer
// protocol), reads and writes scene parameters by Mitsuba's names, and runs the analysis the
// command line runs. The Python half (candela/__init__.py and the modules beside it) gives it
// its Pythonic and Mitsuba-like surface.
//
// Interruption: a render runs on a worker thread while the calling thread, holding the GIL every
// 50 ms, asks Python whether a signal is pending (PyErr_CheckSignals): Ctrl-C raises
// KeyboardInterrupt in the caller after the render stopped at its next tile, and the process
// stays usable. The progress callback runs on the calling thread too.

#include "analysis/compare_modes.h"
#include "analysis/convergence.h"
#include "analysis/expression.h"
#include "analysis/image_metrics.h"
#include "analysis/validation.h"
#include "core/bsdf.h"
#include "core/error.h"
#include "core/file_output.h"
#include "core/filter.h"
#include "core/image.h"
#include "core/integrator.h"
#include "core/mesh.h"
#include "core/parameters.h"
#include "core/progress.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/variant.h"
#include "core/xml.h"
#include "integrators/estimators.h"
#include "viewer/view_server.h"

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <candela/version.h>

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <thread>

namespace py = pybind11;
using namespace candela;

namespace {

// A loaded scene, and the lock that keeps a parameter update from racing a render.
struct SceneHandle {
    Ref<Scene> scene;
    std::shared_ptr<std::mutex> lock = std::make_shared<std::mutex>();
};

// Pixels Candela owns, H x W x C float32, seen by NumPy through the buffer protocol.
struct ImageBuffer {
    Image image;
};

py::object errors_module() { return py::module_::import("candela.errors"); }

// Runs `body` with the GIL released, translating Candela's errors into the package's exceptions.
template <typename F>
auto without_gil(F&& body) {
    py::gil_scoped_release release;
    return body();
}

void register_exceptions(py::module_& m) {
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const SceneError& e) {
            py::object error = errors_module().attr("SceneError")(e.what(), e.location.file, e.location.line, e.message());
            PyErr_SetObject(error.get_type().ptr(), error.ptr());
        } catch (const InputError& e) {
            PyErr_SetString(errors_module().attr("InputError").ptr(), e.what());
        } catch (const InternalError& e) {
            PyErr_SetString(errors_module().attr("InternalError").ptr(), e.what());
        }
    });
}

SceneParameters string_map(const std::map<std::string, std::string>& params) { return SceneParameters(params.begin(), params.end()); }

// The variant of a Mitsuba name that Candela renders in (core/variant.h); InputError otherwise.
Variant variant_of(const std::string& name) {
    const std::optional<Variant> v = parse_variant(name);
    if (!v) throw InputError("\"" + name + "\" is not a variant (known: " + variant_names() + ")");
    return *v;
}

SceneHandle load_file(const std::string& path, const std::map<std::string, std::string>& params, const std::string& variant, int sensor) {
    const Variant v = variant_of(variant);
    return without_gil([&] { return SceneHandle{load_scene(path, string_map(params), v, sensor)}; });
}

SceneHandle load_string(const std::string& xml, const std::string& virtual_path, const std::map<std::string, std::string>& params,
                        const std::string& variant, int sensor) {
    const Variant v = variant_of(variant);
    return without_gil([&] { return SceneHandle{load_scene_from_string(xml, virtual_path, string_map(params), v, sensor)}; });
}

// The XML tag of a plugin type ("diffuse" -> "bsdf"), or None. "merge" is a shape the loader
// expands (core/xml.cpp), not a registered plugin.
py::object plugin_tag(const std::string& type) {
    if (type == "merge") return py::str("shape");
    for (ObjectKind kind :
         {ObjectKind::Shape, ObjectKind::BSDF, ObjectKind::Emitter, ObjectKind::Texture, ObjectKind::Sensor, ObjectKind::Film,
          ObjectKind::Filter, ObjectKind::Sampler, ObjectKind::Integrator, ObjectKind::Medium, ObjectKind::Phase, ObjectKind::Volume}) {
        const auto names = plugin_names(kind);
        if (std::find(names.begin(), names.end(), type) != names.end()) return py::str(kind_tag(kind));
    }
    return py::none();
}

// Renders on a worker thread; the calling thread waits with the GIL, checking for signals and
// reporting progress.
ImageBuffer render(SceneHandle& handle, int spp, uint64_t seed, int threads, const std::string& integrator_xml, py::object progress,
                   const std::vector<std::string>& aovs) {
    Ref<Scene> scene = handle.scene;
    Ref<Integrator> integrator;
    // Loaded in the scene's variant: an integrator that does not render in it is refused as it
    // would be in the scene's file.
    if (!integrator_xml.empty())
        integrator =
            without_gil([&] { return load_scene_from_string(integrator_xml, "<integrator>.xml", {}, scene->variant())->integrator_ref(); });
    std::atomic<bool> interrupt{false};
    ProgressSink sink;
    RenderOptions options;
    options.spp = spp;
    options.seed = seed;
    options.threads = threads;
    options.aovs = aovs;
    options.interrupt = &interrupt;
    options.progress_sink = &sink;
    RenderResult result;
    std::exception_ptr failure;
    std::mutex done_mutex;
    std::condition_variable done_signal;
    bool done = false;
    std::thread worker([&] {
        try {
            std::lock_guard<std::mutex> lock(*handle.lock);
            Integrator& chosen = integrator ? *integrator : scene->integrator();
            result = chosen.render(*scene, options);
            annotate_image(result.image, result.stats, chosen.to_string(), scene->source_file);
        } catch (...) {
            failure = std::current_exception();
        }
        std::lock_guard<std::mutex> lock(done_mutex);
        done = true;
        done_signal.notify_all();
    });
    // A Python exception (KeyboardInterrupt, or one the progress callback raised) stops the
    // render and is raised once the worker has finished.
    std::optional<py::error_already_set> python_error;
    for (;;) {
        {
            py::gil_scoped_release release;
            std::unique_lock<std::mutex> lock(done_mutex);
            done_signal.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; });
            if (done) break;
        }
        if (python_error) continue;
        if (PyErr_CheckSignals() != 0) {
            python_error.emplace();
            interrupt = true;
            continue;
        }
        if (!progress.is_none()) {
            try {
                progress(sink.fraction());
            } catch (py::error_already_set& e) {
                python_error.emplace(std::move(e));
                interrupt = true;
            }
        }
    }
    {
        py::gil_scoped_release release;
        worker.join();
    }
    if (python_error) throw std::move(*python_error);
    if (failure) std::rethrow_exception(failure);
    if (!progress.is_none()) progress(1.0);
    return ImageBuffer{std::move(result.image)};
}

py::buffer_info image_buffer(ImageBuffer& b) {
    Image& img = b.image;
    const ssize_t c = img.channel_count(), w = img.width(), h = img.height();
    return py::buffer_info(img.data().data(), sizeof(float), py::format_descriptor<float>::format(), 3, {h, w, c},
                           {ssize_t(sizeof(float)) * w * c, ssize_t(sizeof(float)) * c, ssize_t(sizeof(float))});
}

ImageBuffer image_from_array(py::array_t<float, py::array::c_style | py::array::forcecast> array, const std::vector<std::string>& channels,
                             const std::map<std::string, std::string>& metadata) {
    if (array.ndim() != 3) throw InputError("an image array is height x width x channels");
    const int h = int(array.shape(0)), w = int(array.shape(1)), c = int(array.shape(2));
    if (int(channels.size()) != c)
        throw InputError(std::to_string(channels.size()) + " channel names for " + std::to_string(c) + " channels");
    std::vector<float> values(array.data(), array.data() + size_t(h) * w * c);
    Image img(w, h, channels, std::move(values));
    img.metadata = metadata;
    return ImageBuffer{std::move(img)};
}

// The PNG bytes of 8-bit sRGB pixels (H x W x 3 uint8), through the image module's writer.
py::bytes png_bytes(py::array_t<uint8_t, py::array::c_style | py::array::forcecast> pixels) {
    if (pixels.ndim() != 3 || pixels.shape(2) != 3) throw InputError("encode_png expects H x W x 3 bytes");
    const int h = int(pixels.shape(0)), w = int(pixels.shape(1));
    Image display = Image::rgb(w, h);
    const uint8_t* p = pixels.data();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x, p += 3) display.set_rgb(x, y, Spectrum(p[0], p[1], p[2]) / 255.0f);
    return py::bytes(without_gil([&] { return encode_png(display); }));
}

void write_png_file(py::array_t<uint8_t, py::array::c_style | py::array::forcecast> pixels, const std::string& path) {
    const py::bytes png = png_bytes(pixels);
    write_file_atomically(path, std::string(png));
}

// --- parameters -------------------------------------------------------------------------------

const char* type_name(ParameterType t) {
    switch (t) {
        case ParameterType::Float: return "float";
        case ParameterType::Color: return "color";
        case ParameterType::Transform: return "transform";
        default: return "floats";
    }
}

std::vector<SceneParameter> parameters_of(SceneHandle& h) { return scene_parameters(*h.scene); }

py::list parameter_list(SceneHandle& h) {
    py::list out;
    for (const SceneParameter& p : parameters_of(h)) out.append(py::make_tuple(p.name, type_name(p.access.type)));
    return out;
}

const SceneParameter& find_parameter(const std::vector<SceneParameter>& all, const std::string& name) {
    for (const SceneParameter& p : all)
        if (p.name == name) return p;
    throw py::key_error("the scene has no parameter \"" + name + "\"");
}

py::array_t<float> get_parameter(SceneHandle& h, const std::string& name) {
    const auto all = parameters_of(h);
    std::lock_guard<std::mutex> lock(*h.lock);
    const std::vector<float> v = find_parameter(all, name).access.get();
    py::array_t<float> out(ssize_t(v.size()));
    std::copy(v.begin(), v.end(), out.mutable_data());
    return out;
}

// Writes the values of `changes` (name -> flat float array), then updates their owners once.
void set_parameters(SceneHandle& h, const std::map<std::string, py::array_t<float, py::array::c_style | py::array::forcecast>>& changes) {
    const auto all = parameters_of(h);
    std::vector<std::pair<const SceneParameter*, std::vector<float>>> writes;
    for (const auto& [name, array] : changes) {
        const SceneParameter& p = find_parameter(all, name);
        if (!p.access.set) throw InputError("parameter \"" + name + "\" is read-only");
        writes.emplace_back(&p, std::vector<float>(array.data(), array.data() + array.size()));
    }
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(*h.lock);
    for (const auto& [p, values] : writes) {
        const size_t count = p->access.get().size();
        if (values.size() != count)
            throw InputError("parameter \"" + p->name + "\" holds " + std::to_string(count) + " numbers, not " +
                             std::to_string(values.size()));
        for (float x : values)
            if (!std::isfinite(x)) throw InputError("parameter \"" + p->name + "\" must be finite");
    }
    // A setter may still refuse its value (a singular transform, a field of view beyond 180
    // degrees): what was written before it is brought up to date all the same.
    std::vector<const SceneParameter*> changed;
    try {
        for (const auto& [p, values] : writes) {
            p->access.set(values);
            changed.push_back(p);
        }
    } catch (...) {
        apply_parameter_changes(*h.scene, changed);
        throw;
    }
    apply_parameter_changes(*h.scene, changed);
}

// Throws Python's IndexError unless 0 <= index < count ("sensor index 3 is out of range: the
// scene has 2 sensor(s)").
void check_index(const char* what, int index, size_t count) {
    if (index < 0 || size_t(index) >= count)
        throw py::index_error(std::string(what) + " index " + std::to_string(index) + " is out of range: the scene has " +
                              std::to_string(count) + " " + what + "(s)");
}

// What Python's scene.sensors() shows of sensor `index`: its plugin type, id, pose, shutter,
// film and sample count, as the scene holds them now (traverse changes included).
py::dict sensor_info(SceneHandle& h, int index) {
    std::lock_guard<std::mutex> lock(*h.lock);
    check_index("sensor", index, size_t(h.scene->sensor_count()));
    const Sensor& sensor = h.scene->sensor_at(index);
    const Film& film = sensor.film();
    py::array_t<float> to_world({4, 4});
    const Mat4& m = sensor.to_world().matrix();  // column-major: m[col][row]
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) to_world.mutable_at(r, c) = m[c][r];
    auto pair = [](const Vec2i& v) { return py::make_tuple(v.x, v.y); };
    py::dict info;
    info["type"] = sensor.to_string();
    info["id"] = sensor.id;
    info["to_world"] = to_world;
    info["shutter_open"] = sensor.shutter_open();
    info["shutter_open_time"] = sensor.shutter_open_time();
    info["film_type"] = film.to_string();
    info["film_size"] = pair(film.full_size());
    info["crop_size"] = pair(film.crop_size());
    info["crop_offset"] = pair(film.crop_offset());
    info["sampler_type"] = sensor.sampler().to_string();
    info["spp"] = sensor.sampler().sample_count();
    return info;
}

py::tuple bbox_tuple(const BoundingBox& b) {
    return py::make_tuple(py::make_tuple(b.min.x, b.min.y, b.min.z), py::make_tuple(b.max.x, b.max.y, b.max.z));
}

// What Python's scene.shapes() shows of shape `index` (Scene::shapes() order): its plugin type,
// id, bounds, area, mesh sizes, and which emitter, sensor and BSDF it carries.
py::dict shape_info(SceneHandle& h, int index) {
    std::lock_guard<std::mutex> lock(*h.lock);
    const auto& shapes = h.scene->shapes();
    check_index("shape", index, shapes.size());
    const Shape& shape = *shapes[size_t(index)];
    py::dict info;
    info["type"] = shape.to_string();
    info["id"] = shape.id;
    info["bbox"] = bbox_tuple(shape.bbox());
    info["surface_area"] = shape.surface_area();
    const auto* mesh = dynamic_cast<const Mesh*>(&shape);
    info["is_mesh"] = mesh != nullptr;
    info["vertex_count"] = mesh ? mesh->positions().size() : 0;
    info["face_count"] = mesh ? mesh->triangle_count() : 0;
    int emitter_index = -1;
    const auto& emitters = h.scene->emitters();
    for (size_t i = 0; i < emitters.size(); ++i)
        if (shape.emitter() && emitters[i].get() == shape.emitter()) emitter_index = int(i);
    info["emitter_index"] = emitter_index;
    int sensor_index = -1;
    for (int i = 0; i < h.scene->sensor_count(); ++i)
        if (shape.attached_sensor() && &h.scene->sensor_at(i) == shape.attached_sensor().get()) sensor_index = i;
    info["sensor_index"] = sensor_index;
    info["bsdf_type"] = shape.bsdf() ? shape.bsdf()->to_string() : std::string();
    info["bsdf_id"] = shape.bsdf() ? shape.bsdf()->id : std::string();
    return info;
}

// What Python's scene.emitters() shows of emitter `index` (area emitters first, as Scene keeps
// them): its plugin type, id, whether it is at infinity, and the shape it lies on.
py::dict emitter_info(SceneHandle& h, int index) {
    std::lock_guard<std::mutex> lock(*h.lock);
    const auto& emitters = h.scene->emitters();
    check_index("emitter", index, emitters.size());
    const Emitter& emitter = *emitters[size_t(index)];
    int shape_index = -1;
    const auto& shapes = h.scene->shapes();
    for (size_t i = 0; i < shapes.size(); ++i)
        if (emitter.shape() && shapes[i].get() == emitter.shape()) shape_index = int(i);
    py::dict info;
    info["type"] = emitter.to_string();
    info["id"] = emitter.id;
    info["is_environment"] = emitter.is_infinite();
    info["shape_index"] = shape_index;
    return info;
}

// --- analysis ---------------------------------------------------------------------------------

py::dict comparison_dict(const ImageComparison& c) {
    py::dict d;
    d["rmse"] = c.rmse;
    d["relmse"] = c.relmse;
    d["mare"] = c.mare;
    d["block_mare"] = c.block_mare;
    d["blocks_used"] = c.blocks_used;
    d["blocks_total"] = c.blocks_total;
    d["mean_test"] = std::vector<float>{c.mean_test.x, c.mean_test.y, c.mean_test.z};
    d["mean_reference"] = std::vector<float>{c.mean_reference.x, c.mean_reference.y, c.mean_reference.z};
    d["mean_relative_difference"] =
        std::vector<float>{c.mean_relative_difference.x, c.mean_relative_difference.y, c.mean_relative_difference.z};
    return d;
}

py::dict compare(const ImageBuffer& test, const ImageBuffer& reference, int block_size, float heatmap_range) {
    ImageComparison c;
    Image heatmap;
    without_gil([&] {
        c = compare_images(test.image, reference.image, block_size);
        heatmap = relative_difference_heatmap(test.image, reference.image, heatmap_range);
        return 0;
    });
    py::dict d = comparison_dict(c);
    d["heatmap"] = ImageBuffer{std::move(heatmap)};
    std::string reason;
    d["agree"] = images_agree(c, AgreementThresholds{}, &reason);
    d["reason"] = reason;
    return d;
}

py::dict converge(SceneHandle& h, const std::vector<int>& spp_counts, py::object expected, py::object reference, uint64_t seed,
                  int threads) {
    std::unique_ptr<ImageBuffer> reference_image;
    ConvergenceTarget target;
    if (!reference.is_none()) {
        reference_image = std::make_unique<ImageBuffer>(reference.cast<ImageBuffer>());
        target = reference_target(reference_image->image);
    } else {
        target = constant_target(expected.cast<double>());
    }
    RenderOptions base;
    base.seed = seed;
    base.threads = threads;
    ConvergenceStudy study;
    without_gil([&] {
        std::lock_guard<std::mutex> lock(*h.lock);
        study = study_convergence(*h.scene, target, spp_counts, base, ConvergenceCriteria{});
        return 0;
    });
    py::list counts;
    for (const CountError& c : study.counts) {
        py::dict e;
        e["spp"] = c.spp;
        e["rmse"] = c.rmse;
        e["rmse_se"] = c.rmse_se;
        e["relmse"] = c.relmse;
        e["bias"] = c.bias;
        e["bias_se"] = c.bias_se;
        e["seconds"] = c.seconds;
        counts.append(e);
    }
    py::dict d;
    d["counts"] = counts;
    d["slope"] = study.slope.slope;
    d["slope_se"] = study.slope.slope_se;
    d["slope_fitted"] = study.slope.status == SlopeFit::Status::Fitted;
    d["failures"] = study.failures;
    d["converges"] = study.failures.empty();
    char name[] = "/tmp/candela-plot-XXXXXX.png";
    const int fd = mkstemps(name, 4);
    if (fd >= 0) {
        ::close(fd);
        std::filesystem::remove(name);
        write_convergence_plot(study.counts, name);
        d["plot"] = ImageBuffer{read_image(name)};
        std::filesystem::remove(name);
    }
    return d;
}

py::dict validate(const std::string& scene_path, const std::string& reference_path, int spp, int reference_spp, int threads,
                  const std::string& variant) {
    ValidationSettings settings;
    settings.variant = variant_of(variant);
    settings.spp = spp;
    settings.reference_spp = reference_spp;
    settings.threads = threads;
    SceneValidation v;
    without_gil([&] {
        v = validate_scene(ValidationCase{std::filesystem::path(scene_path).stem().string(), scene_path, reference_path}, settings);
        return 0;
    });
    py::dict d = comparison_dict(v.metrics);
    d["name"] = v.name;
    d["passed"] = v.pass;
    d["compared"] = v.compared;
    d["reason"] = v.reason;
    d["z_threshold"] = v.z.threshold;
    d["z_tested"] = v.z.tested;
    d["z_rejected"] = v.z.rejected;
    d["seconds"] = v.seconds;
    d["spp"] = v.spp;
    return d;
}

py::dict estimate_irradiance_points(SceneHandle& h, py::array_t<float, py::array::c_style | py::array::forcecast> points,
                                    py::array_t<float, py::array::c_style | py::array::forcecast> normals, uint64_t samples, uint64_t seed,
                                    int threads, int max_depth) {
    if (points.ndim() != 2 || points.shape(1) != 3 || normals.ndim() != 2 || normals.shape(1) != 3 || points.shape(0) != normals.shape(0))
        throw InputError("points and normals are N x 3 arrays of the same N");
    EstimatorOptions options;
    options.samples = samples;
    options.seed = seed;
    options.threads = threads;
    options.path.max_depth = max_depth;
    const ssize_t n = points.shape(0);
    py::array_t<float> mean({n, ssize_t(3)}), error({n, ssize_t(3)});
    std::vector<Estimate> estimates(static_cast<size_t>(n));
    without_gil([&] {
        std::lock_guard<std::mutex> lock(*h.lock);
        for (ssize_t i = 0; i < n; ++i) {
            const Vec3 p(points.at(i, 0), points.at(i, 1), points.at(i, 2)), nn(normals.at(i, 0), normals.at(i, 1), normals.at(i, 2));
            if (!all_finite(p) || !all_finite(nn) || squared_length(nn) == 0.0f)
                throw InputError("point " + std::to_string(i) + ": its position and normal must be finite, the normal non-zero");
            estimates[size_t(i)] = estimate_irradiance(*h.scene, p, nn, options);
        }
        return 0;
    });
    for (ssize_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            mean.mutable_at(i, c) = estimates[size_t(i)].mean[c];
            error.mutable_at(i, c) = estimates[size_t(i)].std_error[c];
        }
    py::dict d;
    d["mean"] = mean;
    d["std_error"] = error;
    d["samples"] = samples;
    return d;
}

py::dict estimate_radiance_ray(SceneHandle& h, std::vector<float> origin, std::vector<float> direction, uint64_t samples, uint64_t seed,
                               int threads, int max_depth) {
    if (origin.size() != 3 || direction.size() != 3) throw InputError("origin and direction are three numbers each");
    EstimatorOptions options;
    options.samples = samples;
    options.seed = seed;
    options.threads = threads;
    options.path.max_depth = max_depth;
    Estimate e = without_gil([&] {
        std::lock_guard<std::mutex> lock(*h.lock);
        return estimate_radiance(*h.scene, Vec3(origin[0], origin[1], origin[2]), Vec3(direction[0], direction[1], direction[2]), options);
    });
    py::dict d;
    d["mean"] = std::vector<float>{e.mean.x, e.mean.y, e.mean.z};
    d["std_error"] = std::vector<float>{e.std_error.x, e.std_error.y, e.std_error.z};
    d["samples"] = e.samples;
    return d;
}

py::dict compare_modes(SceneHandle& h, const std::string& methods, int spp, py::object reference, int reference_spp, int threads,
                       float heatmap_range) {
    const std::vector<std::string> specs = split_methods(methods);
    std::vector<Ref<Integrator>> integrators;  // all built first: a bad method stops before any render
    for (const std::string& spec : specs) integrators.push_back(method_integrator(spec, *h.scene));
    RenderResult ref;
    if (!reference.is_none()) ref.image = linear_rgb(reference.cast<ImageBuffer>().image);
    std::vector<MethodRun> runs;
    without_gil([&] {
        std::lock_guard<std::mutex> lock(*h.lock);
        if (reference.is_none()) ref = reference_render(*h.scene, reference_spp, threads);
        for (size_t k = 0; k < specs.size(); ++k) runs.push_back(run_method(specs[k], integrators[k], *h.scene, spp, threads, ref.image));
        return 0;
    });
    py::list out;
    for (MethodRun& r : runs) {
        py::dict d = comparison_dict(r.comparison);
        d["method"] = r.label;
        d["seconds"] = r.result.stats.seconds;
        d["bake_seconds"] = r.bake_seconds;
        d["mean_luminance_difference"] = mean_luminance_difference(r.comparison);
        d["heatmap"] = ImageBuffer{relative_difference_heatmap(r.result.image, ref.image, heatmap_range)};
        d["image"] = ImageBuffer{r.result.image};
        out.append(d);
    }
    const std::string label = reference.is_none() ? "path tracer, " + std::to_string(reference_spp) + " spp" : "the given image";
    py::dict d;
    d["methods"] = out;
    d["table"] = methods_table(runs, label);
    d["sheet"] = ImageBuffer{methods_contact_sheet(runs, ref, {"REFERENCE", reference.is_none() ? "PATH TRACER" : "GIVEN"}, heatmap_range)};
    d["reference"] = ImageBuffer{std::move(ref.image)};
    return d;
}

// The live viewer (candela.view): its server runs until stop() or the object is gone.
struct ViewerHandle {
    std::unique_ptr<ViewServer> server;
};

ViewerHandle start_viewer(SceneHandle& h, int port, const std::string& bind) {
    return without_gil([&] {
        return ViewerHandle{std::make_unique<ViewServer>(h.scene, h.scene->source_file, ViewServerOptions{bind, port})};
    });
}

}  // namespace

PYBIND11_MODULE(_candela, m) {
    m.doc() = "Candela's native module (see the candela package)";
    register_exceptions(m);
    m.def("version", [] { return std::string(CANDELA_VERSION); });

    py::class_<SceneHandle>(m, "Scene", "A loaded scene (candela.load_file, load_string, load_dict)")
        .def_property_readonly("integrator", [](const SceneHandle& h) { return h.scene->integrator().to_string(); })
        .def_property_readonly("path", [](const SceneHandle& h) { return h.scene->source_file; })
        .def_property_readonly("sensor_count", [](const SceneHandle& h) { return h.scene->sensor_count(); })
        .def_property_readonly("sensor_index", [](const SceneHandle& h) { return h.scene->sensor_index(); })
        .def_property_readonly("shape_count", [](const SceneHandle& h) { return h.scene->shapes().size(); })
        .def_property_readonly("emitter_count", [](const SceneHandle& h) { return h.scene->emitters().size(); })
        .def_property_readonly("film_size",
                               [](const SceneHandle& h) {
                                   const Vec2i s = h.scene->sensor().film().crop_size();
                                   return py::make_tuple(s.x, s.y);
                               })
        .def_property_readonly("spp", [](const SceneHandle& h) { return h.scene->sensor().sampler().sample_count(); })
        .def_property_readonly(
            "variant", [](const SceneHandle& h) { return std::string(variant_name(h.scene->variant())); },
            "The variant the scene was loaded in (Mitsuba's name: scalar_rgb or scalar_spectral)")
        .def_property_readonly(
            "parameters", [](const SceneHandle& h) { return h.scene->parameters; },
            "The scene file's $name parameters after <default>s and overrides (analytic scenes state "
            "their exact answer as \"expected\")")
        .def("__repr__", [](const SceneHandle& h) {
            const Vec2i s = h.scene->sensor().film().crop_size();
            return "candela.Scene(" + h.scene->source_file + ", " + h.scene->integrator().to_string() + ", " + std::to_string(s.x) + " x " +
                   std::to_string(s.y) + ")";
        });

    py::class_<ImageBuffer>(m, "ImageBuffer", py::buffer_protocol())
        .def(py::init(&image_from_array), py::arg("array"), py::arg("channels"), py::arg("metadata") = std::map<std::string, std::string>{})
        .def_buffer(&image_buffer)
        .def_property_readonly("channels", [](const ImageBuffer& b) { return b.image.channels(); })
        .def_property_readonly("metadata", [](const ImageBuffer& b) { return b.image.metadata; });

    py::class_<ViewerHandle>(m, "Viewer", "The live viewer's server (candela.view)")
        .def_property_readonly("url", [](const ViewerHandle& v) { return v.server ? v.server->url() : std::string(); })
        .def_property_readonly("port", [](const ViewerHandle& v) { return v.server ? v.server->port() : 0; })
        .def_property_readonly("clients", [](const ViewerHandle& v) { return v.server ? v.server->clients() : 0; })
        .def("stop", [](ViewerHandle& v) {
            py::gil_scoped_release release;
            if (v.server) v.server->stop();
            v.server.reset();
        });
    m.def("evaluate_expression", [](const std::string& text) { return evaluate_expression(text); });
    m.def("start_viewer", &start_viewer, py::arg("scene"), py::arg("port"), py::arg("bind"));
    m.def("load_file", &load_file, py::arg("path"), py::arg("params"), py::arg("variant") = "scalar_rgb", py::arg("sensor") = 0);
    m.def("load_string", &load_string, py::arg("xml"), py::arg("virtual_path"), py::arg("params"), py::arg("variant") = "scalar_rgb",
          py::arg("sensor") = 0);
    m.def("plugin_tag", &plugin_tag, py::arg("type"));
    m.def("render", &render, py::arg("scene"), py::arg("spp"), py::arg("seed"), py::arg("threads"), py::arg("integrator_xml"),
          py::arg("progress"), py::arg("aovs"));
    m.def("read_image", [](const std::string& path) { return without_gil([&] { return ImageBuffer{read_image(path)}; }); });
    m.def("write_exr", [](const ImageBuffer& b, const std::string& path, bool float32) {
        without_gil([&] {
            write_exr(b.image, path, float32);
            return 0;
        });
    });
    m.def("encode_png", &png_bytes);
    m.def("write_png", &write_png_file);
    m.def("parameter_list", &parameter_list);
    m.def("get_parameter", &get_parameter);
    m.def("set_parameters", &set_parameters);
    m.def("sensor_info", &sensor_info, py::arg("scene"), py::arg("index"));
    m.def("shape_info", &shape_info, py::arg("scene"), py::arg("index"));
    m.def("emitter_info", &emitter_info, py::arg("scene"), py::arg("index"));
    m.def(
        "film_filter",
        [](SceneHandle& h, py::array_t<double, py::array::c_style | py::array::forcecast> offsets) {
            const ReconstructionFilter& filter = h.scene->sensor().film().filter();
            py::array_t<double> weights(offsets.size());
            for (ssize_t i = 0; i < offsets.size(); ++i) weights.mutable_data()[i] = filter.eval(float(offsets.data()[i]));
            return py::make_tuple(filter.radius(), weights);
        },
        py::arg("scene"), py::arg("offsets"),
        "The reconstruction filter of the scene's film: its radius (pixels) and its 1D weights at `offsets` (pixels)");
    m.def(
        "scene_bbox",
        [](SceneHandle& h) {
            std::lock_guard<std::mutex> lock(*h.lock);
            return bbox_tuple(h.scene->bbox());
        },
        "The scene's bounds (its shapes'), as (min, max); an empty scene's min is +inf, its max -inf");
    m.def("compare", &compare, py::arg("test"), py::arg("reference"), py::arg("block_size"), py::arg("heatmap_range"));
    m.def("converge", &converge, py::arg("scene"), py::arg("spp_counts"), py::arg("expected"), py::arg("reference"), py::arg("seed"),
          py::arg("threads"));
    m.def("validate", &validate, py::arg("scene_path"), py::arg("reference_path"), py::arg("spp"), py::arg("reference_spp"),
          py::arg("threads"), py::arg("variant") = "scalar_rgb");
    m.def("estimate_irradiance", &estimate_irradiance_points, py::arg("scene"), py::arg("points"), py::arg("normals"), py::arg("samples"),
          py::arg("seed"), py::arg("threads"), py::arg("max_depth"));
    m.attr("default_compared_methods") = DefaultComparedMethods;
    m.def("compare_modes", &compare_modes, py::arg("scene"), py::arg("methods"), py::arg("spp"), py::arg("reference"),
          py::arg("reference_spp"), py::arg("threads"), py::arg("heatmap_range"));
    m.def("estimate_radiance", &estimate_radiance_ray, py::arg("scene"), py::arg("origin"), py::arg("direction"), py::arg("samples"),
          py::arg("seed"), py::arg("threads"), py::arg("max_depth"));
}
