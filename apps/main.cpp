// candela: the command line of the Candela renderer.

#include "apps/commands.h"

#include "core/stop.h"

#include <candela/version.h>

#include <string>

int main(int argc, char** argv) {
    CLI::App app{"Candela " CANDELA_VERSION ": a physically based renderer for Mitsuba 3 scene files"};
    app.name("candela");
    app.require_subcommand(1);
    app.set_version_flag("--version", CANDELA_VERSION);
    // Ctrl-C and SIGTERM end any command at once with 130 or 143, but `render`, which stops
    // gracefully and writes what it has (core/stop.h). Chosen before parsing, so that a signal
    // that arrives at any moment of a render's life gets the render's treatment.
    const bool render = argc > 1 && std::string(argv[1]) == "render";
    candela::set_stop_mode(render ? candela::StopMode::Graceful : candela::StopMode::Immediate);
    std::function<int()> run;
    candela::app::add_render_command(app, run);
    candela::app::add_compare_command(app, run);
    candela::app::add_estimate_command(app, run);
    candela::app::add_converge_command(app, run);
    candela::app::add_validate_command(app, run);
    candela::app::add_compare_modes_command(app, run);
    candela::app::add_merge_command(app, run);
    candela::app::add_farm_command(app, run);
    candela::app::add_view_command(app, run);
    int code = 0;
    if (candela::app::refuse_unknown_command(app, argc, argv, code)) return code;
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return candela::app::report_parse_error(app, e);
    }
    code = candela::app::run_guarded(run);
    // A command that stopped early on a signal ends with the signal's code, whatever it returned.
    return candela::stop_exit_code() ? candela::stop_exit_code() : code;
}
