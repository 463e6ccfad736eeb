// What every subcommand shares about its arguments: numbers checked with a message that says
// what is expected, the scene file and its -D parameters, and the parse errors a newcomer meets
// (a misspelled command or option, a missing scene) turned into a message with a way forward.

#include "apps/commands.h"

#include "core/error.h"
#include "core/text.h"
#include "core/variant.h"
#include "core/warning.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <thread>

namespace candela::app {

namespace {

bool parse_number(const std::string& text, double& value) {
    if (text.empty()) return false;
    char* end = nullptr;
    value = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size() && std::isfinite(value);
}

std::vector<std::string> option_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::Option* o : app.get_options()) {
        for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
        for (const std::string& s : o->get_snames()) names.push_back("-" + s);
    }
    return names;
}

// The subcommand the arguments name (the deepest one given), for messages about it.
const CLI::App* invoked(const CLI::App& app) {
    for (const CLI::App* sub : app.get_subcommands())
        if (sub->parsed()) {
            const CLI::App* deeper = invoked(*sub);
            return deeper ? deeper : sub;
        }
    return nullptr;
}

std::string command_path(const CLI::App* app) {
    std::string path;
    for (const CLI::App* a = app; a; a = a->get_parent())
        path = (a->get_parent() ? a->get_name() : "candela") + (path.empty() ? "" : " ") + path;
    return path;
}

std::vector<CLI::App*> subcommands_of(const CLI::App& app) {
    return const_cast<CLI::App&>(app).get_subcommands([](CLI::App*) { return true; });
}

std::string subcommand_list(const CLI::App& app) {
    std::string list;
    size_t width = 0;
    for (const CLI::App* sub : subcommands_of(app)) width = std::max(width, sub->get_name().size());
    for (const CLI::App* sub : subcommands_of(app))
        list += "\n  " + sub->get_name() + std::string(width + 2 - sub->get_name().size(), ' ') + sub->get_description();
    return list;
}

// "candela compare TEST REFERENCE [OPTIONS]": the command with its positional arguments.
std::string usage(const CLI::App& command) {
    std::string line = command_path(&command);
    for (const CLI::Option* o : command.get_options())
        if (o->get_positional()) {
            std::string name = o->get_name();
            std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::toupper(c)); });
            line += " " + name + (o->get_items_expected_max() > 1 ? "..." : "");
        }
    return line + " [OPTIONS] (" + command_path(&command) + " --help lists the options)";
}

}  // namespace

CLI::Validator whole_number(const std::string& option, const std::string& unit, long long minimum, long long maximum) {
    const std::string what = option + " must be a whole number" + (unit.empty() ? "" : " of " + unit);
    const std::string range =
        maximum == LLONG_MAX ? ">= " + std::to_string(minimum) : "in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]";
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            long long v = 0;
            const bool whole = parse_integer(text, v);
            if (whole && v > maximum) return what + ", at most " + std::to_string(maximum) + " (got " + text + ")";
            if (!whole || v < minimum) return what + ", at least " + std::to_string(minimum) + " (got " + text + ")";
            return "";
        },
        "INT " + range);
}

CLI::Validator positive_number(const std::string& option) {
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            double v;
            if (!parse_number(text, v) || !(v > 0.0)) return option + " must be a number greater than 0 (got " + text + ")";
            return "";
        },
        "NUMBER > 0");
}

CLI::Validator non_negative_number(const std::string& option) {
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            double v;
            if (!parse_number(text, v) || !(v >= 0.0)) return option + " must be a number, 0 or more (got " + text + ")";
            return "";
        },
        "NUMBER >= 0");
}

CLI::Validator one_of(const std::string& option, const std::vector<std::string>& choices) {
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            if (std::find(choices.begin(), choices.end(), text) != choices.end()) return "";
            const std::string nearest = suggested_name(text, choices);
            return option + " must be one of " + list + " (got " + text + ")" + (nearest.empty() ? "" : "; did you mean " + nearest + "?");
        },
        "");
}

void check_exr_output(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (extension == ".exr") return;
    const std::string exr = std::filesystem::path(path).replace_extension(".exr").string();
    throw InputError(
        "-o " + path + ": the image is written as OpenEXR (radiance in floating point), so its name ends in .exr: -o " + exr +
        (extension == ".png" || extension == ".jpg" || extension == ".jpeg" ? " (render's --png writes an 8-bit preview beside it)" : ""));
}

void add_seed_option(CLI::App* cmd, int64_t& seed, const std::string& default_text) {
    cmd->add_option("--seed", seed, "Random seed (" + default_text + ")")->check(whole_number("--seed", "", 0, LLONG_MAX));
}

void add_threads_option(CLI::App* cmd, int& threads) {
    cmd->add_option("--threads,-t", threads, "Worker threads (default 0: one per core; more than the cores is capped to them)")
        ->check(whole_number("--threads", "threads", 0, 4096))
        ->each([](const std::string& text) {
            const int cores = int(std::thread::hardware_concurrency());
            if (cores > 0 && std::stoi(text) > cores)
                warn(SourceLocation{}, "--threads " + text + ": this machine has " + std::to_string(cores) + " cores; using " +
                                           std::to_string(cores) + " threads");
        });
}

void add_variant_option(CLI::App* cmd, std::string& variant) {
    cmd->add_option("--variant", variant,
                    std::string("What radiance carries, by Mitsuba 3's variant names: scalar_rgb (default), scalar_spectral "
                                "(wavelengths sampled per path; measured spectra used per wavelength) or "
                                "scalar_spectral_polarized (spectral, with Stokes vectors and Mueller matrices)"))
        ->check([](const std::string& name) -> std::string {
            auto v = parse_variant(name);
            if (!v) return "--variant \"" + name + "\" is not a variant (known: " + variant_names() + ")";
            return "";
        });
}

void SceneInput::add_to(CLI::App* cmd) {
    cmd->add_option("scene", words, "Scene file (Mitsuba 3 XML)")->required()->expected(1, -1);
    add_variant_option(cmd, variant);
    cmd->add_option("-D", defines, "Set a scene parameter: -D name=value (repeatable: -D a=1 -D b=2)")
        ->expected(1)
        ->allow_extra_args(false)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    add_search_path_option(cmd, search_path);
    cmd->add_option("-s,--sensor", sensor, "Which of the scene's sensors to render, counted from 0 in file order (default 0)")
        ->check(whole_number("--sensor", "", 0, INT_MAX));
}

const std::string& SceneInput::resolve() {
    if (!scene.empty()) return scene;
    // name=value words among the positional arguments are parameters (the older form
    // -D a=1 b=2, where the second is not behind a -D of its own).
    std::vector<std::string> files;
    for (const std::string& word : words) {
        const size_t eq = word.find('=');
        if (eq != std::string::npos && eq > 0 && word.find('/') > eq)
            defines.push_back(word);
        else
            files.push_back(word);
    }
    if (files.empty()) throw InputError("no scene file given: the words were all parameters (give SCENE.xml -D name=value ...)");
    if (files.size() > 1) {
        std::string rest;
        for (size_t i = 1; i < files.size(); ++i) rest += (rest.empty() ? "" : " ") + files[i];
        throw InputError("one scene file, please: got " + files[0] + " and also " + rest +
                         " (parameters are -D name=value, one per -D; an option's value follows the option)");
    }
    scene = files[0];
    return scene;
}

Ref<Scene> SceneInput::load() {
    resolve();
    use_search_folders(search_path);
    return load_scene(scene, parse_defines(defines), *parse_variant(variant), sensor);
}

bool refuse_unknown_command(const CLI::App& app, int argc, char** argv, int& code) {
    // An option before any command is the program's own (--help, --version) or a mistake.
    if (argc > 1 && argv[1][0] == '-' && std::string(argv[1]) != "--") {
        const std::string name = std::string(argv[1]).substr(0, std::string(argv[1]).find('='));
        const std::vector<std::string> options = option_names(app);
        if (std::find(options.begin(), options.end(), name) == options.end()) {
            const std::string nearest = suggested_name(name, options);
            std::cerr << "error: unknown option " << name << " for candela" << (nearest.empty() ? "" : "; did you mean " + nearest + "?")
                      << " (options belong after the command: candela "
                      << "COMMAND [OPTIONS]; the commands are:" << subcommand_list(app) << ")\n";
            code = ExitBadInput;
            return true;
        }
    }
    // The command word, and for a command with commands of its own (farm plan) the next one too.
    const CLI::App* level = &app;
    for (int i = 1; i < argc && argv[i][0] != '-'; ++i) {
        const std::vector<CLI::App*> subs = subcommands_of(*level);
        if (subs.empty()) return false;
        const std::string name = argv[i];
        std::vector<std::string> names;
        const CLI::App* found = nullptr;
        for (const CLI::App* sub : subs) {
            names.push_back(sub->get_name());
            if (sub->get_name() == name) found = sub;
        }
        if (found) {
            level = found;
            continue;
        }
        if (name == "help" && level == &app) {
            std::cout << const_cast<CLI::App&>(app).help();
            code = ExitOk;
            return true;
        }
        const std::string nearest = suggested_name(name, names);
        const std::string where = command_path(level);
        std::cerr << "error: unknown command \"" << name << "\"" << (level == &app ? "" : " for " + where)
                  << (nearest.empty() ? "" : "; did you mean \"" + nearest + "\"?") << "\nThe commands are:" << subcommand_list(*level)
                  << "\n(" << where << " COMMAND --help tells more)\n";
        code = ExitBadInput;
        return true;
    }
    return false;
}

int report_parse_error(const CLI::App& app, const CLI::ParseError& e) {
    const CLI::App* command = invoked(app);
    const std::string where = command ? command_path(command) : "candela";
    if (dynamic_cast<const CLI::CallForHelp*>(&e) || dynamic_cast<const CLI::CallForAllHelp*>(&e) ||
        dynamic_cast<const CLI::CallForVersion*>(&e)) {
        const int code = const_cast<CLI::App&>(app).exit(e);
        return code == 0 ? ExitOk : ExitBadInput;
    }
    std::string message = e.what();
    if (dynamic_cast<const CLI::ValidationError*>(&e)) {
        // CLI11 puts the option's name first; the validators' messages name it themselves.
        const size_t colon = message.find(": ");
        if (colon != std::string::npos && message.compare(colon + 2, 1, "-") == 0) message = message.substr(colon + 2);
    } else if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
        // The words nothing took, each with what it may have meant.
        std::vector<std::string> words;
        const size_t colon = message.find(": ");
        std::string rest = colon == std::string::npos ? "" : message.substr(colon + 2), word;
        for (char c : rest + " ") {
            if (c == ' ') {
                if (!word.empty()) words.insert(words.begin(), word);  // CLI11 lists them last first
                word.clear();
            } else {
                word += c;
            }
        }
        const std::vector<std::string> options = command ? option_names(*command) : option_names(app);
        message.clear();
        for (const std::string& w : words) {
            if (!message.empty()) message += "\nerror: ";
            if (w.size() > 1 && w[0] == '-') {
                const std::string name = w.substr(0, w.find('='));
                const std::string nearest = suggested_name(name, options);
                message += "unknown option " + name + " for " + where + (nearest.empty() ? "" : "; did you mean " + nearest + "?") + " (" +
                           where + " --help lists the options)";
            } else {
                message += "unexpected argument \"" + w + "\" for " + where + " (a value belongs right after its option; " + where +
                           " --help lists them)";
            }
        }
    } else if (dynamic_cast<const CLI::RequiredError*>(&e)) {
        const size_t end = message.find(" is required");
        const CLI::Option* option = command && end != std::string::npos ? command->get_option_no_throw(message.substr(0, end)) : nullptr;
        if (message.rfind("A subcommand", 0) == 0)
            message = where + " needs a command:" + subcommand_list(command ? *command : app);
        else if (option && option->get_positional())
            message = where + " needs its input: " + option->get_name() + " (" + option->get_description() + "); usage: " + usage(*command);
        else if (option)
            message = where + " needs " + option->get_name() + ": " + option->get_description() + "; usage: " + usage(*command);
    } else if (dynamic_cast<const CLI::ArgumentMismatch*>(&e)) {
        // An option at the end of the line, or followed by another option, without its value.
        const std::string name = message.substr(0, message.find(':'));
        const CLI::Option* option = command ? command->get_option_no_throw(name) : nullptr;
        if (option) message = "option " + name + " needs a value after it: " + option->get_description();
    } else if (dynamic_cast<const CLI::ConversionError*>(&e)) {
        message += " (" + where + " --help says what each option takes)";
    }
    std::cerr << "error: " << message << "\n";
    return ExitBadInput;
}

}  // namespace candela::app
