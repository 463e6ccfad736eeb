// candela farm plan  SCENE -o OUT.exr --parts N [--spp S] [--seed S] [--sampler NAME] [-D k=v]...
//                    [-a FOLDER]... [--aov ...] [--regions CxR] [--workdir DIR] [--threads-per-task K]
//                    [--force]
// candela farm slurm SCENE -o OUT.exr --parts N [the same] [--partition P] [--time T] [--mem M]
//                    [--submit]
// candela farm status WORKDIR
// A render split into N sample ranges (times C x R image regions): `plan` prints the render
// commands, one per part, and the merge command, for any scheduler; `slurm` writes an sbatch job
// array and a merge job that depends on it (afterok) and with --submit submits both; `status`
// reports the parts done and missing and the time left. A work folder that holds a plan is not
// planned over without --force (its parts may be rendering). See farm/plan.h.

#include "apps/commands.h"

#include "core/error.h"
#include "core/scene.h"
#include "farm/plan.h"
#include "farm/resumable_render.h"
#include "farm/shell.h"
#include "farm/status.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;

namespace candela::app {

namespace {

struct FarmArgs {
    SceneInput input;
    std::string output, workdir, regions = "1x1", sampler;
    int parts = 0, spp = 0, threads_per_task = 1;
    int64_t seed = -1;
    std::vector<std::string> aovs;
    SlurmOptions slurm;
    bool submit = false, force = false;
};

void add_plan_options(CLI::App* cmd, FarmArgs& a) {
    a.input.add_to(cmd);
    cmd->add_option("-o,--output", a.output, "The final image")->required();
    cmd->add_option("--parts", a.parts, "Number of sample ranges")->required()->check(whole_number("--parts", "parts", 1, MaxSampleCount));
    cmd->add_option("--spp", a.spp, "Samples per pixel (default: the scene's sampler's sample_count)")
        ->check(whole_number("--spp", "samples", 1, MaxSampleCount));
    add_seed_option(cmd, a.seed, "default: the scene's sampler's");
    add_sampler_option(cmd, a.sampler);
    cmd->add_option("--aov", a.aovs, "Extra EXR layers: albedo, normal, depth, variance, samples")->delimiter(',');
    cmd->add_flag("--force", a.force, "Replace the plan of a work folder that already has one");
    cmd->add_option("--regions", a.regions, "Also split the image into C x R regions, as CxR (default 1x1)");
    cmd->add_option("--workdir", a.workdir, "Folder for the parts, logs and scripts (default: OUT's name with -farm, beside it)");
    cmd->add_option("--threads-per-task", a.threads_per_task, "Threads (and Slurm CPUs) per part (default 1)")
        ->check(whole_number("--threads-per-task", "threads", 1, 4096));
}

// The request: the scene loaded once here to resolve spp, seed and size and to refuse
// integrators that cannot render parts before anything is queued.
FarmRequest make_request(FarmArgs& a) {
    FarmRequest r;
    r.candela = program_path();
    r.scene = fs::absolute(a.input.resolve()).lexically_normal().string();
    r.output = fs::absolute(a.output).lexically_normal().string();
    check_output_path(r.output);
    check_exr_output(r.output);
    r.workdir = a.workdir.empty() ? (fs::path(r.output).parent_path() / (fs::path(r.output).stem().string() + "-farm")).string()
                                  : fs::absolute(a.workdir).lexically_normal().string();
    const fs::path plan_file = fs::path(r.workdir) / "plan.txt";
    std::error_code ec;
    if (fs::exists(plan_file, ec) && !a.force)
        throw InputError(plan_file.string() + ": this work folder already has a farm plan, whose parts may be rendering or rendered; " +
                         "`candela farm status " + r.workdir + "` shows them; --force replaces the plan, or choose another --workdir");
    r.defines = a.input.defines;
    r.search_path = absolute_search_folders(a.input.search_path);
    r.aovs = a.aovs;
    r.sampler = a.sampler;
    r.variant = a.input.variant;
    r.sensor = a.input.sensor;
    AovLayout check_names(a.aovs);
    Ref<Scene> scene = a.input.load();
    if (std::string reason = scene->integrator().parts_refusal(); !reason.empty())
        throw InputError("the " + scene->integrator().to_string() + " integrator cannot render parts: " + reason +
                         "; a farm needs one that can (path, direct, ao, irradiance, ...)");
    RenderOptions options;  // spp and seed as the parts' renders resolve them (a sampler may round spp up)
    options.spp = a.spp;
    options.sampler = a.sampler;
    if (a.seed >= 0) options.seed = uint64_t(a.seed);
    const RenderStats planned = planned_render(*scene, options);
    r.spp = planned.spp;
    r.seed = planned.seed;
    r.image = scene->sensor().film().crop_size();
    r.parts = a.parts;
    if (std::sscanf(a.regions.c_str(), "%dx%d", &r.regions.x, &r.regions.y) != 2)
        throw InputError("--regions expects CxR, got \"" + a.regions + "\"");
    r.threads_per_task = a.threads_per_task;
    return r;
}

// Runs `sbatch --parsable ARGS...` and returns the job id it prints.
std::string sbatch(const std::vector<std::string>& args) {
    std::vector<std::string> words = {"sbatch", "--parsable"};
    words.insert(words.end(), args.begin(), args.end());
    FILE* pipe = ::popen((shell_join(words) + " 2>&1").c_str(), "r");
    if (!pipe) throw InputError("cannot run sbatch");
    std::string out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, pipe)) out += buf;
    int status = ::pclose(pipe);
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    if (status != 0) {
        if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
            throw InputError("sbatch not found: install Slurm's client (Debian: slurm-client), or submit the scripts yourself");
        throw InputError(shell_join(words) + " failed: " + out);
    }
    // The last line is "<job id>" or "<job id>;<cluster>".
    std::string id = out.substr(out.find_last_of('\n') + 1);
    id = id.substr(0, id.find(';'));
    if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
        throw InputError(shell_join(words) + " printed no job id: " + out);
    return id;
}

// Where the plan went, on stderr (stdout holds the commands, one per line, for a script).
void report_plan(const FarmPlan& plan) {
    std::cerr << "wrote the plan " << (fs::path(plan.workdir) / "plan.txt").string() << " (" << plan.tasks.size() << " parts, written to "
              << (fs::path(plan.workdir) / "parts").string() << "; logs in " << (fs::path(plan.workdir) / "logs").string() << ")\n";
}

int run_plan(FarmArgs& a) {
    FarmPlan plan = plan_farm(make_request(a));
    write_plan(plan);
    report_plan(plan);
    for (const FarmTask& t : plan.tasks) std::cout << t.command << "\n";
    std::cout << plan.merge_command << "\n";
    return ExitOk;
}

int run_slurm(FarmArgs& a) {
    FarmRequest request = make_request(a);
    FarmPlan plan = plan_farm(request);
    write_plan(plan);
    report_plan(plan);
    SlurmOptions options = a.slurm;
    options.threads_per_task = request.threads_per_task;
    write_slurm_scripts(plan, "candela-" + fs::path(request.scene).stem().string(), options);
    const std::string render = render_script_path(plan.workdir), merge = merge_script_path(plan.workdir);
    std::cout << "wrote " << render << " (a job array of " << plan.tasks.size() << " tasks) and " << merge << "\n";
    if (!a.submit) {
        std::cout << "submit with: job=$(sbatch --parsable " << shell_quote(render) << ") && sbatch --dependency=afterok:$job "
                  << shell_quote(merge) << "\n";
        return ExitOk;
    }
    const std::string render_job = sbatch({render});
    const std::string merge_job = sbatch({"--dependency=afterok:" + render_job, merge});
    std::cout << "render job " << render_job << " (array of " << plan.tasks.size() << " tasks)\n";
    std::cout << "merge job " << merge_job << " (runs when every task succeeded)\n";
    std::cout << "progress: " << shell_join({program_path(), "farm", "status", plan.workdir}) << "\n";
    return ExitOk;
}

}  // namespace

void add_farm_command(CLI::App& app, std::function<int()>& run) {
    CLI::App* farm = app.add_subcommand("farm", "Split a render across a cluster: plan, Slurm job scripts, status");
    farm->require_subcommand(1);

    auto plan_args = std::make_shared<FarmArgs>();
    CLI::App* plan = farm->add_subcommand("plan", "Print the render command of every part and the merge command, one per line");
    add_plan_options(plan, *plan_args);
    plan->callback([plan_args, &run] { run = [plan_args] { return run_plan(*plan_args); }; });

    auto slurm_args = std::make_shared<FarmArgs>();
    CLI::App* slurm = farm->add_subcommand("slurm", "Write an sbatch job array and a merge job that depends on it; --submit submits them");
    add_plan_options(slurm, *slurm_args);
    slurm->add_option("--partition", slurm_args->slurm.partition, "Slurm partition");
    slurm->add_option("--time", slurm_args->slurm.time, "Time limit per task (Slurm syntax, e.g. 2:00:00)");
    slurm->add_option("--mem", slurm_args->slurm.mem, "Memory per task (Slurm syntax, e.g. 8G)");
    slurm->add_flag("--submit", slurm_args->submit, "Submit both jobs with sbatch and print their ids");
    slurm->callback([slurm_args, &run] { run = [slurm_args] { return run_slurm(*slurm_args); }; });

    auto workdir = std::make_shared<std::string>();
    CLI::App* status = farm->add_subcommand("status", "Parts done and missing, and the time left, of a farm's work folder");
    status->add_option("workdir", *workdir, "The farm's work folder")->required();
    status->callback([workdir, &run] {
        run = [workdir] {
            std::cout << farm_status(*workdir);
            return ExitOk;
        };
    });
}

}  // namespace candela::app
