#include "farm/resumable_render.h"

#include "core/error.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "farm/coverage.h"

#include <unistd.h>
#include <chrono>

namespace candela {

namespace {

double seconds_since_epoch() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

std::string host_name() {
    char host[256] = {0};
    return ::gethostname(host, sizeof host - 1) == 0 ? std::string(host) : std::string();
}

bool inside(const CoverageBox& box, const CoverageBox& target) {
    return rect_inside(box.rect, target.rect) && box.samples.begin >= target.samples.begin && box.samples.end <= target.samples.end;
}

// Reads the part to continue into `result`, after checking that it belongs to this render.
void resume_from(const std::string& path, const CoverageBox& target, ResumableResult& result) {
    PartHeader h = read_part_header(path);
    if (std::string d = result.header.identity.difference(h.identity); !d.empty())
        throw InputError(path + ": cannot resume this render from it: it belongs to another render: " + d);
    for (const CoverageBox& b : h.coverage)
        if (!inside(b, target))
            throw InputError(path + ": cannot resume this render from it: it holds " + describe(b, h.identity.image) +
                             ", outside what this render renders (" + describe(target, h.identity.image) + ")");
    add_part(h, result.sums);
    PartHeader& r = result.header;
    r.coverage = h.coverage;
    r.work = h.work;
    r.started = h.started;
    r.host = h.host;
}

// Adds one render of a missing box into `result`.
void add_render(RenderResult& part, ResumableResult& result) {
    PartHeader& h = result.header;
    // Nothing held yet (a render from scratch): take the sums, bit for bit and without a second
    // copy of the image's sums.
    if (result.sums.rect().empty())
        result.sums = std::move(part.sums);
    else
        result.sums.add(part.sums);
    h.coverage.insert(h.coverage.end(), part.coverage.begin(), part.coverage.end());
    h.work.add_work(part.stats);
    result.stats.add_work(part.stats);
}

// What is rendered so far plus what the running render holds, written as a part.
void write_checkpoint(const ResumableResult& so_far, const PixelSums& running, const std::vector<CoverageBox>& running_coverage,
                      const std::string& output) {
    PartHeader h = so_far.header;
    if (so_far.sums.rect().empty()) {
        h.coverage = running_coverage;
        h.partial = true;
        h.finished = seconds_since_epoch();
        write_part(output, running, h);  // nothing held before this render: no copy
        return;
    }
    PixelSums sums = so_far.sums;
    sums.add(running);
    h.coverage.insert(h.coverage.end(), running_coverage.begin(), running_coverage.end());
    h.coverage = coalesce(h.coverage);
    h.partial = true;
    h.finished = seconds_since_epoch();
    write_part(output, sums, h);
}

// The target must be pixels of the image and sample indices of the render.
void check_target(const CoverageBox& t, const Vec2i& image, int spp) {
    if (!rect_inside_image(t.rect, image))
        throw InputError("region " + format_rect(t.rect) + " is not inside the " + std::to_string(image.x) + " x " +
                         std::to_string(image.y) + " image");
    if (t.samples.begin < 0 || t.samples.empty() || t.samples.end > spp)
        throw InputError("sample range " + format_sample_range(t.samples) + " is not a non-empty part of [0, " + std::to_string(spp) + ")");
}

}  // namespace

RenderStats planned_render(const Scene& scene, const RenderOptions& options) {
    const Ref<Sampler> sampler = configured_sampler(scene, options);
    RenderStats s;
    s.spp = sampler->sample_count();
    s.seed = sampler->seed();
    s.sampler = sampler->to_string();
    return s;
}

ResumableResult render_resumable(const Scene& scene, RenderOptions options, const ResumableRequest& request) {
    if (std::string reason = scene.integrator().parts_refusal(); !reason.empty())
        throw InputError("the " + scene.integrator().to_string() + " integrator cannot render a part (--samples, --crop), resume or " +
                         "checkpoint: " + reason);
    const auto* integrator = dynamic_cast<const SamplingIntegrator*>(&scene.integrator());
    if (!integrator) throw InputError("the " + scene.integrator().to_string() + " integrator keeps no pixel sums");
    ResumableResult result;
    result.stats = planned_render(scene, options);
    check_target(request.target, scene.sensor().film().crop_size(), result.stats.spp);
    const AovLayout layout(options.aovs);
    const SampleLayout values = SampleLayout::of_film(scene.sensor().film(), integrator->channel_names());
    PartHeader& h = result.header;
    h.identity = render_identity(scene, request.scene_path, result.stats, values, layout, request.command);
    h.started = seconds_since_epoch();
    h.host = host_name();
    // Allocated when a resumed part needs it, else taken from the first render (add_render).
    const ImageRect rect = sums_rect(scene.sensor().film(), request.target.rect);
    if (!request.resume.empty()) {
        result.sums = PixelSums(rect, values, layout);
        resume_from(request.resume, request.target, result);
    }

    const std::vector<CoverageBox> missing = uncovered(h.coverage, request.target);
    for (const CoverageBox& box : missing) {
        if (options.interrupt && options.interrupt->load()) {
            result.interrupted = true;
            break;
        }
        options.region = box.rect;
        options.samples = box.samples;
        if (request.checkpoint_seconds > 0.0) {
            options.checkpoint_seconds = request.checkpoint_seconds;
            options.checkpoint = [&](const PixelSums& running, const std::vector<CoverageBox>& coverage) {
                write_checkpoint(result, running, coverage, request.output);
            };
        }
        RenderResult part = scene.integrator().render(scene, options);
        add_render(part, result);
        if (part.stats.partial) {
            result.interrupted = true;
            break;
        }
    }
    if (result.sums.rect().empty()) result.sums = PixelSums(rect, values, layout);  // interrupted before any render
    h.coverage = coalesce(h.coverage);
    h.partial = !uncovered(h.coverage, request.target).empty();
    h.finished = seconds_since_epoch();
    result.stats.partial = h.partial;
    return result;
}

}  // namespace candela
