#pragma once
// The subcommands of the `candela` program. Each registers its options on a CLI11 subcommand and
// returns the process exit code: 0 success, 1 a check that failed (compare, validate, converge),
// 2 bad input (scene errors name file:line), 70 an internal error (a bug), 128 + signal when stopped
// by Ctrl-C (130) or SIGTERM (143).

#include "core/integrator.h"
#include "core/math.h"
#include "core/xml.h"
#include "integrators/raster/raster.h"

#include <CLI/CLI.hpp>

#include <climits>
#include <functional>
#include <map>

namespace candela::app {

constexpr int ExitOk = 0;
constexpr int ExitCheckFailed = 1;
constexpr int ExitBadInput = 2;
constexpr int ExitInternalError = 70;  // EX_SOFTWARE: a broken internal contract (InternalError)

// Adds a subcommand to `app`; `run` is set to the function that executes it after parsing.
void add_render_command(CLI::App& app, std::function<int()>& run);
void add_compare_command(CLI::App& app, std::function<int()>& run);
void add_estimate_command(CLI::App& app, std::function<int()>& run);
void add_converge_command(CLI::App& app, std::function<int()>& run);
void add_validate_command(CLI::App& app, std::function<int()>& run);
void add_compare_modes_command(CLI::App& app, std::function<int()>& run);
void add_merge_command(CLI::App& app, std::function<int()>& run);
void add_farm_command(CLI::App& app, std::function<int()>& run);
void add_view_command(CLI::App& app, std::function<int()>& run);

// The raster mode's options on the command line (render --mode raster, compare-modes): those of
// raster_options() marked for it (--aa-filter sets aa_filter, ...), their choices in --help.
struct RasterOptionArgs {
    std::map<std::string, std::string> values;  // by option name; empty when not given
    std::map<std::string, bool> flags;          // the boolean options, by name

    void add_to(CLI::App* cmd);
    // The options that were given, by RasterSettings name.
    std::map<std::string, std::string> given() const;
    // Applies the given options; InputError for an invalid value.
    void apply(RasterSettings& settings) const;
};

// --sampler NAME (any registered sampler plugin, checked when parsing) and the adaptive sampling
// options (--adaptive-threshold, --adaptive-min-spp, --adaptive-step), for the commands that
// render with RenderOptions.
void add_sampler_option(CLI::App* cmd, std::string& sampler);
void add_adaptive_options(CLI::App* cmd, AdaptiveSampling& adaptive);

// Shared by the commands: -D name=value pairs, and "x,y,z" triples (InputError when malformed).
SceneParameters parse_defines(const std::vector<std::string>& defines);
// -a FOLDER (Mitsuba's `mitsuba -a`): folders searched for the files a scene names, after the
// scene's own folder and the working directory; repeatable, and "a;b" gives several at once.
// use_search_folders hands them to FileResolver::set_search_folders (InputError if one is missing).
void add_search_path_option(CLI::App* cmd, std::vector<std::string>& folders);
void use_search_folders(const std::vector<std::string>& folders);
// The folders of -a options, each absolute: what a command run elsewhere (a farm part, a resume)
// passes on.
std::vector<std::string> absolute_search_folders(const std::vector<std::string>& folders);
Vec3 parse_triple(const std::string& text, const std::string& option);

// The absolute path of this program (for commands that other machines run).
std::string program_path();

// Runs `body`, turning scene and input errors into a message on stderr and exit code 2.
int run_guarded(const std::function<int()>& body);

// Checks of numeric options with messages that say what is expected: "--spp must be a whole
// number of samples, at least 1 (got 0)".
CLI::Validator whole_number(const std::string& option, const std::string& unit, long long minimum, long long maximum = LLONG_MAX);
CLI::Validator positive_number(const std::string& option);
CLI::Validator non_negative_number(const std::string& option);
// A name from a list, with the nearest one suggested: "--mode must be one of path, raster (got
// rastr); did you mean raster?".
CLI::Validator one_of(const std::string& option, const std::vector<std::string>& choices);
// InputError unless the output's name ends in .exr (what render, merge and farm write), with the
// name that would do.
void check_exr_output(const std::string& path);
// --seed S (a whole number, 0 or more); `default_text` says what it is when not given.
// --variant NAME: Mitsuba's variant names (core/variant.h); a name that is none, or a variant not
// implemented, is a parse error naming the known ones.
void add_variant_option(CLI::App* cmd, std::string& variant);
void add_seed_option(CLI::App* cmd, int64_t& seed, const std::string& default_text);
// --threads N (0, the default: one per core).
void add_threads_option(CLI::App* cmd, int& threads);
// The scene a command reads: the scene file (positional), -D name=value (one per -D and
// repeatable, as Mitsuba's; the older "-D a=1 b=2" still works: name=value words among the
// positional arguments are parameters), -a FOLDER and -s/--sensor N (Mitsuba's: which of the
// scene's sensors to render, 0 by default).
struct SceneInput {
    std::string scene;  // the scene file, once resolve() has sorted the words
    std::vector<std::string> words, defines, search_path;
    std::string variant = "scalar_rgb";  // --variant: Mitsuba's variant name (core/variant.h)
    int sensor = 0;                      // -s/--sensor

    void add_to(CLI::App* cmd);
    // Sorts the positional words into the scene file and parameters: InputError for no scene
    // file or more than one (naming the words and the order that works).
    const std::string& resolve();
    // resolve(), the -a folders in use, and the scene loaded with the -D parameters.
    Ref<Scene> load();
};
// Before parsing: a misspelled command ("rendr", "farm pln") gets the nearest command and the list
// (exit 2), `candela help` the help (exit 0); true when it answered (with `code`).
bool refuse_unknown_command(const CLI::App& app, int argc, char** argv, int& code);
// A parse error as a message that names the problem and a way forward (an unknown option's
// nearest name, the usage); returns the exit code (2, or 0 for --help).
int report_parse_error(const CLI::App& app, const CLI::ParseError& e);

}  // namespace candela::app
