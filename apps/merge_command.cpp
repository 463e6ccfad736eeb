// candela merge PART.exr|FOLDER... -o OUT.exr [--allow-partial] [--sums]
// Adds up the parts of a split render (render --samples/--crop, farm) and writes the image. The
// parts must belong to one render and must not overlap (else exit code 2); when they leave samples
// out, it names them with the commands that render them and refuses (exit code 2), or with
// --allow-partial writes the mean of what there is, marked candela.partial. --sums writes a part
// holding all of them instead, for a merge tree.

#include "apps/commands.h"

#include "core/error.h"
#include "core/progress.h"
#include "farm/merge.h"

#include <cmath>
#include <cstdio>
#include <iostream>

namespace candela::app {

namespace {
struct MergeArgs {
    std::vector<std::string> parts;
    std::string output;
    bool allow_partial = false, sums = false;
};
// "16 spp", or for a partial merge "8 of 16 spp" (samples per pixel on average over the image).
std::string samples_held(const MergeSet& set) {
    const std::string total = std::to_string(set.identity.spp) + " spp";
    if (set.missing.empty()) return total;
    double missing = 0.0;
    for (const CoverageBox& b : set.missing)
        missing += double(b.rect.size.x) * double(b.rect.size.y) * double(b.samples.end - b.samples.begin);
    const double pixels = double(set.identity.image.x) * double(set.identity.image.y);
    const double held = double(set.identity.spp) - missing / pixels;
    char buf[64];
    std::snprintf(buf, sizeof buf, held == std::floor(held) ? "%.0f of " : "%.2f (on average) of ", held);
    return buf + total;
}

}  // namespace

void add_merge_command(CLI::App& app, std::function<int()>& run) {
    auto args = std::make_shared<MergeArgs>();
    CLI::App* cmd = app.add_subcommand("merge", "Merge the parts of a split render (render --samples/--crop, farm) into the image");
    cmd->add_option("parts", args->parts, "Part files, or folders of part files (*.exr)")->required();
    cmd->add_option("-o,--output", args->output, "Output EXR")->required();
    cmd->add_flag("--allow-partial", args->allow_partial, "With samples missing, write the mean of what there is, marked partial");
    cmd->add_flag("--sums", args->sums, "Write a part holding all the given parts (for merging in a tree), not the image");
    cmd->callback([args, &run] {
        run = [args] {
            check_output_path(args->output);
            check_exr_output(args->output);
            MergeSet set = check_parts(args->parts);
            if (args->sums) {
                merge_into_part(set, args->output);
                std::cerr << "wrote " << args->output << ": one part holding " << set.parts.size() << " parts\n";
                return ExitOk;
            }
            if (!set.missing.empty() && !args->allow_partial) {
                std::cerr << "error: the parts hold " << samples_held(set) << " of the " << set.identity.image.x << " x "
                          << set.identity.image.y << " image, not the whole render; nothing written:\n"
                          << describe_missing(set) << "(--allow-partial writes the image of what there is)\n";
                return ExitBadInput;
            }
            Image image = merge_image(set);
            write_exr(image, args->output, set.identity.float32);
            std::cerr << "wrote " << args->output << ": " << set.parts.size() << (set.parts.size() == 1 ? " part, " : " parts, ")
                      << samples_held(set) << ", " << format_duration(std::stod(image.metadata["candela.renderTime"])) << " of rendering\n";
            if (!set.missing.empty()) std::cerr << "warning: partial image, marked candela.partial:\n" << describe_missing(set);
            return ExitOk;
        };
    });
}

}  // namespace candela::app
