// candela: the command line of the Candela renderer.

#include "apps/commands.h"

#include <candela/version.h>

int main(int argc, char** argv) {
    CLI::App app{"Candela " CANDELA_VERSION ": a physically based renderer for Mitsuba 3 scene files"};
    app.require_subcommand(1);
    app.set_version_flag("--version", CANDELA_VERSION);
    std::function<int()> run;
    candela::app::add_render_command(app, run);
    candela::app::add_compare_command(app, run);
    candela::app::add_estimate_command(app, run);
    candela::app::add_converge_command(app, run);
    candela::app::add_validate_command(app, run);
    candela::app::add_compare_modes_command(app, run);
    candela::app::add_merge_command(app, run);
    candela::app::add_farm_command(app, run);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int code = app.exit(e);
        return code == 0 ? 0 : candela::app::ExitBadInput;
    }
    return candela::app::run_guarded(run);
}
