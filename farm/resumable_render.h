#pragma once
// A render that keeps what it adds up (core/pixel_sums.h), so that it can be split, interrupted,
// checkpointed and continued: `candela render` runs every Monte Carlo render through it. It
// renders a target (pixels x sample indices: the whole render, or a part given by --samples and
// --crop), less what a resumed part (--resume) already holds, and reports what it holds when it
// stops, in the one partial-render file format (farm/part_file.h).

#include "farm/part_file.h"

#include <string>

namespace candela {

struct ResumableRequest {
    std::string scene_path;  // as given on the command line
    std::string command;     // the command that repeats the render (RenderIdentity::command)
    CoverageBox target;      // what to render
    std::string resume;      // a part to continue ("" for none)
    // Every this many seconds (0: never) a checkpoint part is written atomically to `output`.
    double checkpoint_seconds = 0.0;
    std::string output;
};

struct ResumableResult {
    PartHeader header;  // identity, coverage (coalesced), partial, times and counts
    PixelSums sums;     // over the target's pixels and the filter's reach around them
    RenderStats stats;  // of this run (seconds, samples, rays), with spp and seed
    bool interrupted = false;
};

// The spp and seed the render will use: the options' when set, else the scene sampler's.
RenderStats planned_render(const Scene& scene, const RenderOptions& options);

// Renders what the target lacks. InputError (before rendering) when the resumed part belongs to
// another render or holds samples outside the target.
ResumableResult render_resumable(const Scene& scene, RenderOptions options, const ResumableRequest& request);

}  // namespace candela
