#pragma once
// A part of a render: an OpenEXR file (float32) holding the sums a set of samples contributes to
// the image (core/pixel_sums.h), and metadata that says which render it belongs to and what it
// covers. It is the one partial-render file of Candela: a part of a farm render (render --samples,
// --crop), an interrupted render (Ctrl-C, SIGTERM) and a checkpoint (--checkpoint) are all parts;
// `candela merge` adds parts up and divides, `candela render --resume` continues one.
//
// Channels:
//   R G B                          the image so far (sum.RGB / sum.W), to look at; never read back
//   sum.R sum.G sum.B [sum.A] sum.<integrator channel>... sum.W
//                                  filtered sums sum(w v) and sum(w), what the image divides: the
//                                  radiance, the alpha when the film's pixel format has one, the
//                                  integrator's own channels (core/pixel_sums.h: SampleLayout)
//   count.N                        samples that landed in the pixel (when there are AOVs)
//   taken.N                        sample indices taken, dropped ones included (AOV "samples")
//   albedoSum.R..B normalSum.X..Z depthSum.Z   sums of the first-hit values (when asked for)
//   moment1.R..B moment2.R..B      sum(L) and sum(L^2) for the variance layer, each with a
//   moment1lo.R..B moment2lo.R..B  float32 "lo" channel holding what float32 rounded off: the
//                                  variance sum(L^2) - sum(L)^2 / n cancels and needs about
//                                  48 bits; everything else keeps its relative float32 rounding.
// The file's pixels are the rectangle the samples reach: the covered pixels grown by the filter's
// reach (candela.origin: where its first pixel lies in the image).
// Metadata (string attributes): candela.partFormat, the render's identity (candela.scene,
// candela.sceneHash, candela.seed, candela.sampler, candela.spp, candela.imageSize,
// candela.integrator, candela.variant, candela.filmChannels, candela.integratorChannels, candela.aovs, candela.version, candela.float32, candela.command), what the
// part holds (candela.coverage: boxes "x,y,w,h@start:end" joined by ';'; candela.partial: "true"
// when it holds less than it was asked to render, so that it must be resumed or completed) and how
// it was made (candela.renderTime, candela.started, candela.finished, candela.host,
// candela.renderedParts, candela.samples, candela.rays, candela.nonfiniteSamples).

#include "core/pixel_sums.h"
#include "farm/coverage.h"

#include <string>
#include <vector>

namespace candela {

class Scene;

// What makes parts belong to one render: they may only be merged when all of this agrees.
struct RenderIdentity {
    std::string scene;       // the scene file as given (informative; the hash decides)
    std::string scene_hash;  // the scene file, every file it read, its parameters and its sensor
    uint64_t seed = 0;
    std::string sampler;  // the sampler plugin
    int spp = 0;          // samples per pixel of the whole render
    Vec2i image{0};       // the image size (the film's crop window)
    std::string integrator;
    std::string variant = "scalar_rgb";  // core/variant.h (parts written before it existed are RGB)
    std::string film_channels;           // SampleLayout::film_key(): "R,G,B,A", or "bands:" and a specfilm's
    std::string integrator_channels;     // SamplingIntegrator::channel_names(), joined by ','
    std::string aovs;                    // AovLayout::names()
    std::string version;                 // Candela's
    bool float32 = true;                 // the film's component format, which the final image takes
    // The render command without --samples, --crop, -o and --threads; a missing piece is this
    // plus those options.
    std::string command;

    AovLayout layout() const;
    // InputError when film_channels names no pixel format or bands.
    SampleLayout values() const;
    // "" when `other` is the same render, else the first field that differs, both values shown.
    std::string difference(const RenderIdentity& other) const;
};

// A hash (16 hex digits) of the scene file's bytes, the bytes of every file it read (includes,
// meshes, textures, spectra) and its parameters after defaults and -D overrides. Files are hashed
// by content, not name, so copies of a scene in different folders agree.
std::string scene_hash(const Scene& scene);

// The identity of the render of `scene` (read from `scene_path`) that `stats` describe (its spp,
// seed and sampler), with what each sample splats and the command that repeats it.
RenderIdentity render_identity(const Scene& scene, const std::string& scene_path, const RenderStats& stats, const SampleLayout& values,
                               const AovLayout& layout, const std::string& command);

struct PartHeader {
    std::string path;
    RenderIdentity identity;
    std::vector<CoverageBox> coverage;
    bool partial = false;                  // interrupted: it holds less than it was asked to
    ImageRect rect;                        // where the file's pixels lie in the image (write_part: sums.rect())
    double started = 0.0, finished = 0.0;  // seconds since the epoch: first start, last finish
    std::string host;
    int rendered_parts = 1;
    RenderWork work;  // summed over the rendered parts it holds
};

// Writes the part atomically (a killed writer leaves nothing under `path`, or the file that was
// there). InputError when a pixel holds more samples than float32 counts exactly (2^24).
void write_part(const std::string& path, const PixelSums& sums, const PartHeader& header);
// Reads only the metadata; InputError naming the file when it is not a part.
PartHeader read_part_header(const std::string& path);
// Adds the part's sums into `sums` (whose rectangle must contain the part's).
void add_part(const PartHeader& header, PixelSums& sums);

}  // namespace candela
