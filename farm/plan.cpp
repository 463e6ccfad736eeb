#include "farm/plan.h"

#include "core/error.h"
#include "core/file_output.h"
#include "farm/coverage.h"
#include "farm/shell.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace candela {

namespace {

const char* const PlanHeader = "# candela farm plan 1";

// Piece k of n of [0, total): [floor(k total / n), floor((k + 1) total / n)).
int split_point(int k, int n, int total) { return int(int64_t(k) * total / n); }

std::string part_name(size_t index) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "part-%05zu.exr", index);
    return buf;
}

std::vector<std::string> render_command(const FarmRequest& r, const FarmTask& task) {
    std::vector<std::string> cmd = render_words(r);
    cmd.insert(cmd.end(), {"--samples", format_sample_range(task.samples)});
    if (!task.region.empty()) cmd.insert(cmd.end(), {"--crop", format_rect(task.region)});
    cmd.insert(cmd.end(), {"--threads", std::to_string(r.threads_per_task), "--quiet", "-o", task.part});
    return cmd;
}

std::vector<std::string> split_words(const std::string& line) {
    std::vector<std::string> words;
    std::string word;
    std::istringstream in(line);
    while (std::getline(in, word, '\t')) words.push_back(word);
    return words;
}

// The #SBATCH lines both scripts share.
std::string sbatch_resources(const SlurmOptions& o) {
    std::string s;
    if (!o.partition.empty()) s += "#SBATCH --partition=" + o.partition + "\n";
    if (!o.time.empty()) s += "#SBATCH --time=" + o.time + "\n";
    if (!o.mem.empty()) s += "#SBATCH --mem=" + o.mem + "\n";
    return s;
}

void write_script(const std::string& path, const std::string& text) {
    write_file_atomically(path, text);
    fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add);
}

}  // namespace

std::vector<std::string> render_words(const FarmRequest& r) {
    std::vector<std::string> cmd = {r.candela, "render", r.scene, "--spp", std::to_string(r.spp), "--seed", std::to_string(r.seed)};
    for (const std::string& d : r.defines) cmd.insert(cmd.end(), {"-D", d});
    for (const std::string& f : r.search_path) cmd.insert(cmd.end(), {"-a", f});
    if (!r.aovs.empty()) {
        std::string list;
        for (const std::string& a : r.aovs) list += (list.empty() ? "" : ",") + a;
        cmd.insert(cmd.end(), {"--aov", list});
    }
    if (!r.sampler.empty()) cmd.insert(cmd.end(), {"--sampler", r.sampler});
    if (!r.mode.empty()) cmd.insert(cmd.end(), {"--mode", r.mode});
    if (!r.variant.empty() && r.variant != "scalar_rgb") cmd.insert(cmd.end(), {"--variant", r.variant});
    if (r.sensor != 0) cmd.insert(cmd.end(), {"--sensor", std::to_string(r.sensor)});
    return cmd;
}

FarmPlan plan_farm(const FarmRequest& r) {
    if (r.parts < 1) throw InputError("--parts must be at least 1");
    if (r.parts > r.spp)
        throw InputError("--parts " + std::to_string(r.parts) + " exceeds the " + std::to_string(r.spp) +
                         " samples per pixel: every part needs at least one sample index");
    if (r.regions.x < 1 || r.regions.y < 1 || r.regions.x > r.image.x || r.regions.y > r.image.y)
        throw InputError("--regions " + std::to_string(r.regions.x) + "x" + std::to_string(r.regions.y) + " does not fit the " +
                         std::to_string(r.image.x) + " x " + std::to_string(r.image.y) + " image");
    for (const std::string& name : {r.candela, r.scene, r.workdir, r.output})
        if (name.find_first_of("\t\n") != std::string::npos)
            throw InputError("\"" + name + "\": a farm cannot use names with tabs or line breaks");
    FarmPlan plan;
    plan.workdir = r.workdir;
    plan.output = r.output;
    const bool whole = r.regions == Vec2i(1);
    for (int j = 0; j < r.regions.y; ++j)
        for (int i = 0; i < r.regions.x; ++i)
            for (int k = 0; k < r.parts; ++k) {
                FarmTask t;
                t.samples = SampleRange{split_point(k, r.parts, r.spp), split_point(k + 1, r.parts, r.spp)};
                if (!whole) {
                    Vec2i lo(split_point(i, r.regions.x, r.image.x), split_point(j, r.regions.y, r.image.y));
                    Vec2i hi(split_point(i + 1, r.regions.x, r.image.x), split_point(j + 1, r.regions.y, r.image.y));
                    t.region = ImageRect{lo, hi - lo};
                }
                t.part = (fs::path(r.workdir) / "parts" / part_name(plan.tasks.size())).string();
                t.command = shell_join(render_command(r, t));
                plan.tasks.push_back(std::move(t));
            }
    plan.merge_command = shell_join({r.candela, "merge", (fs::path(r.workdir) / "parts").string(), "-o", r.output});
    return plan;
}

void write_plan(const FarmPlan& plan) {
    std::error_code ec;
    for (const char* sub : {"parts", "logs"}) {
        fs::create_directories(fs::path(plan.workdir) / sub, ec);
        if (ec) throw InputError(plan.workdir + ": cannot create the work folder: " + ec.message());
    }
    std::string text = std::string(PlanHeader) +
                       "\n# One line per field, tab-separated; one task line per part: index, samples, region (- for the "
                       "whole image), part file, command.\n";
    text += "output\t" + plan.output + "\n";
    text += "merge\t" + plan.merge_command + "\n";
    for (size_t i = 0; i < plan.tasks.size(); ++i) {
        const FarmTask& t = plan.tasks[i];
        text += "task\t" + std::to_string(i) + "\t" + format_sample_range(t.samples) + "\t" +
                (t.region.empty() ? "-" : format_rect(t.region)) + "\t" + t.part + "\t" + t.command + "\n";
    }
    write_file_atomically((fs::path(plan.workdir) / "plan.txt").string(), text);
}

FarmPlan read_plan(const std::string& workdir) {
    const std::string path = (fs::path(workdir) / "plan.txt").string();
    std::ifstream in(path);
    if (!in) throw InputError(path + ": no farm plan here (written by `candela farm plan` or `candela farm slurm`)");
    FarmPlan plan;
    plan.workdir = workdir;
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (number == 1 && line != PlanHeader) throw InputError(path + ":1: not a candela farm plan");
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> w = split_words(line);
        auto bad = [&]() { return InputError(path + ":" + std::to_string(number) + ": malformed line"); };
        if (w[0] == "output" && w.size() == 2) {
            plan.output = w[1];
        } else if (w[0] == "merge" && w.size() == 2) {
            plan.merge_command = w[1];
        } else if (w[0] == "task" && w.size() == 6) {
            FarmTask t;
            try {
                t.samples = parse_sample_range(w[2]);
                if (w[3] != "-") t.region = parse_rect(w[3]);
            } catch (const InputError& e) {
                throw InputError(path + ":" + std::to_string(number) + ": " + e.what());
            }
            if (w[1] != std::to_string(plan.tasks.size())) throw bad();
            t.part = w[4];
            t.command = w[5];
            plan.tasks.push_back(std::move(t));
        } else {
            throw bad();
        }
    }
    if (plan.tasks.empty()) throw InputError(path + ": the plan lists no tasks");
    return plan;
}

std::string render_script_path(const std::string& workdir) { return (fs::path(workdir) / "render.sbatch").string(); }
std::string merge_script_path(const std::string& workdir) { return (fs::path(workdir) / "merge.sbatch").string(); }

void write_slurm_scripts(const FarmPlan& plan, const std::string& job_name, const SlurmOptions& o) {
    const fs::path logs = fs::path(plan.workdir) / "logs";
    std::string render = "#!/bin/bash\n";
    render += "# Candela render farm, written by `candela farm slurm`: task i of this job array renders part i\n";
    render += "# (plan.txt lists them) into " + (fs::path(plan.workdir) / "parts").string() + ".\n";
    render += "# Re-run single tasks with: sbatch --array=2,5 " + render_script_path(plan.workdir) + "\n";
    render += "#SBATCH --job-name=" + job_name + "-render\n";
    render += "#SBATCH --array=0-" + std::to_string(plan.tasks.size() - 1) + "\n";
    render += "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=" + std::to_string(o.threads_per_task) + "\n";
    render += sbatch_resources(o);
    render += "#SBATCH --output=" + (logs / "render-%a.log").string() + "\n";
    render += "set -euo pipefail\n";
    render += "case \"$SLURM_ARRAY_TASK_ID\" in\n";
    for (size_t i = 0; i < plan.tasks.size(); ++i) render += "  " + std::to_string(i) + ") exec " + plan.tasks[i].command + " ;;\n";
    render += "  *) echo \"no task $SLURM_ARRAY_TASK_ID in this farm\" >&2; exit 2 ;;\nesac\n";
    write_script(render_script_path(plan.workdir), render);

    std::string merge = "#!/bin/bash\n";
    merge += "# Candela render farm, written by `candela farm slurm`: merges the parts into the image. Submitted\n";
    merge += "# with --dependency=afterok:<render job>, it runs once every task succeeded, and is cancelled when\n";
    merge += "# one fails (then re-run the failed tasks, see render.sbatch, and submit this again).\n";
    merge += "#SBATCH --job-name=" + job_name + "-merge\n";
    merge += "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n#SBATCH --kill-on-invalid-dep=yes\n";
    merge += sbatch_resources(o);
    merge += "#SBATCH --output=" + (logs / "merge.log").string() + "\n";
    merge += "set -euo pipefail\n";
    merge += "exec " + plan.merge_command + "\n";
    write_script(merge_script_path(plan.workdir), merge);
}

}  // namespace candela
