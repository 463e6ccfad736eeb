#include "farm/status.h"

#include "core/error.h"
#include "core/progress.h"
#include "farm/part_file.h"
#include "farm/plan.h"

#include <algorithm>
#include <filesystem>

namespace fs = std::filesystem;

namespace candela {

namespace {

// Slurm's --array syntax for task indices: "2,5-7".
std::string array_spec(const std::vector<size_t>& indices) {
    std::string out;
    for (size_t i = 0; i < indices.size();) {
        size_t j = i;
        while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
        out += (out.empty() ? "" : ",") + std::to_string(indices[i]) + (j > i ? "-" + std::to_string(indices[j]) : "");
        i = j + 1;
    }
    return out;
}

std::string task_label(const FarmTask& t) {
    return "samples " + format_sample_range(t.samples) + (t.region.empty() ? "" : " of pixels " + format_rect(t.region));
}

// Whether the part file holds exactly what its task renders; otherwise why not.
std::string check_part(const FarmTask& t, const PartHeader& h, const RenderIdentity& first) {
    if (std::string d = first.difference(h.identity); !d.empty()) return "belongs to another render than the other parts: " + d;
    if (h.partial) return "was interrupted (it holds only " + format_coverage(h.coverage) + "); its task renders it again";
    ImageRect rect = t.region.empty() ? ImageRect{Vec2i(0), h.identity.image} : t.region;
    if (h.coverage.size() != 1 || h.coverage[0].rect.offset != rect.offset || h.coverage[0].rect.size != rect.size ||
        h.coverage[0].samples.begin != t.samples.begin || h.coverage[0].samples.end != t.samples.end)
        return "holds " + format_coverage(h.coverage) + ", not its task's " + task_label(t);
    return "";
}

std::string time_left(const std::vector<PartHeader>& done, size_t missing) {
    double total = 0.0, lo = done[0].work.seconds, hi = lo, start = done[0].started, end = done[0].finished;
    for (const PartHeader& h : done) {
        total += h.work.seconds;
        lo = std::min(lo, h.work.seconds);
        hi = std::max(hi, h.work.seconds);
        start = std::min(start, h.started);
        end = std::max(end, h.finished);
    }
    const double mean = total / double(done.size());
    std::string s =
        "render time per part: mean " + format_duration(mean) + " (" + format_duration(lo) + " to " + format_duration(hi) + ")\n";
    if (missing == 0) return s;
    s += "time left: " + format_duration(mean * double(missing)) + " of rendering (" + std::to_string(missing) + " parts at the mean)";
    if (done.size() >= 2 && end > start) {
        const double rate = double(done.size()) / (end - start);
        s += "; at the rate so far (" + std::to_string(done.size()) + " parts in " + format_duration(end - start) + ") about " +
             format_duration(double(missing) / rate);
    }
    return s + "\n";
}

}  // namespace

std::string farm_status(const std::string& workdir) {
    const FarmPlan plan = read_plan(workdir);
    std::vector<PartHeader> done;
    std::vector<size_t> missing;
    std::string problems;
    for (size_t i = 0; i < plan.tasks.size(); ++i) {
        const FarmTask& t = plan.tasks[i];
        std::error_code ec;
        if (!fs::exists(t.part, ec)) {
            missing.push_back(i);
            continue;
        }
        try {
            PartHeader h = read_part_header(t.part);
            std::string wrong = check_part(t, h, done.empty() ? h.identity : done[0].identity);
            if (!wrong.empty()) throw InputError(t.part + ": " + wrong);
            done.push_back(std::move(h));
        } catch (const InputError& e) {
            problems += std::string("  ") + e.what() + "\n";
            missing.push_back(i);
        }
    }
    std::string s = "farm " + workdir + ": " + std::to_string(done.size()) + " of " + std::to_string(plan.tasks.size()) + " parts done\n";
    if (!problems.empty()) s += "parts that cannot be used (their tasks, below, render them again):\n" + problems;
    if (!missing.empty()) {
        s += "missing: task" + std::string(missing.size() > 1 ? "s " : " ") + array_spec(missing) + "\n";
        for (size_t i : missing)
            s += "  task " + std::to_string(i) + " (" + task_label(plan.tasks[i]) + "): " + plan.tasks[i].command + "\n";
        std::error_code ec;
        if (fs::exists(render_script_path(workdir), ec)) {
            s += "on Slurm: sbatch --array=" + array_spec(missing) + " " + render_script_path(workdir) + "\n";
            s += "  then: sbatch --dependency=afterok:<that job id> " + merge_script_path(workdir) + "\n";
        }
    } else {
        s += "complete; merge with: " + plan.merge_command + "\n";
    }
    if (!done.empty()) s += time_left(done, missing.size());
    std::error_code ec;
    if (fs::exists(plan.output, ec)) s += "merged image: " + plan.output + "\n";
    return s;
}

}  // namespace candela
