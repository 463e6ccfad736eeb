#pragma once
// Splitting a render into parts for a cluster (`candela farm`): N sample ranges, times an optional
// grid of image regions, each a `candela render --samples ... [--crop ...]` command writing one
// part, and the `candela merge` command that makes the image. The work folder holds the parts
// (parts/), the logs (logs/), the plan (plan.txt: what `candela farm status` reads) and, for
// Slurm, a job array script (render.sbatch: task i renders part i) and a merge job script
// (merge.sbatch) that runs once every task succeeded.

#include "core/integrator.h"

#include <string>
#include <vector>

namespace candela {

struct FarmRequest {
    std::string candela;                   // the program, absolute
    std::string scene;                     // absolute
    std::vector<std::string> defines;      // name=value
    std::vector<std::string> search_path;  // -a folders, absolute
    std::vector<std::string> aovs;
    std::string sampler;  // render --sampler, when given
    std::string mode;     // render --mode, when given
    std::string variant;  // render --variant, when not the default
    int sensor = 0;       // render --sensor, when not the first
    int spp = 0;          // the render's (resolved from the scene when not given)
    uint64_t seed = 0;    // likewise
    Vec2i image{0};       // the image size, for the regions
    int parts = 1;        // sample ranges
    Vec2i regions{1, 1};  // columns x rows of image regions
    int threads_per_task = 1;
    std::string workdir, output;  // absolute
};

struct FarmTask {
    SampleRange samples;
    ImageRect region;     // empty: the whole image
    std::string part;     // the part file it writes
    std::string command;  // the render command, as a shell line
};

struct FarmPlan {
    std::string workdir, output;
    std::vector<FarmTask> tasks;
    std::string merge_command;  // a shell line
};

// The words of the command that renders the request's image whole: `candela render SCENE --spp S
// --seed X`, then -D, -a, --aov, --sampler and --mode as given. Parts add --samples and --crop.
std::vector<std::string> render_words(const FarmRequest& request);

// Sample range k of N is [floor(k spp / N), floor((k+1) spp / N)); region (i, j) of a C x R grid
// likewise in x and y. Task index = region index * N + range index. InputError when a range or
// region would be empty.
FarmPlan plan_farm(const FarmRequest& request);

// Creates WORKDIR, WORKDIR/parts and WORKDIR/logs, and writes WORKDIR/plan.txt.
void write_plan(const FarmPlan& plan);
// InputError naming the file when WORKDIR/plan.txt is missing or malformed.
FarmPlan read_plan(const std::string& workdir);

struct SlurmOptions {
    std::string partition, time, mem;  // empty: the cluster's defaults
    int threads_per_task = 1;
};
// Writes WORKDIR/render.sbatch and WORKDIR/merge.sbatch.
void write_slurm_scripts(const FarmPlan& plan, const std::string& job_name, const SlurmOptions& options);
std::string render_script_path(const std::string& workdir);
std::string merge_script_path(const std::string& workdir);

}  // namespace candela
