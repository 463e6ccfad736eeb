// candela view SCENE.xml [--port N] [--bind ADDR] [-D name=value]... [-a FOLDER]... [--threads N]
//
// Serves the scene live to a browser (viewer/, docs/viewer.md): the progressive path tracer and
// the raster mode side by side on one camera, driven from the page. Prints the URL (with its
// token) and serves until Ctrl-C or SIGTERM (exit code 130 or 143).

#include "apps/commands.h"

#include "core/error.h"
#include "core/stop.h"
#include "core/warning.h"
#include "core/xml.h"
#include "viewer/view_server.h"

#include <chrono>
#include <cstdio>
#include <thread>

namespace candela::app {

namespace {

struct ViewArgs {
    SceneInput input;
    std::string bind = "127.0.0.1";
    int port = 0;
};

int view(ViewArgs& a) {
    Ref<Scene> scene = a.input.load();
    if (a.bind != "127.0.0.1" && a.bind != "::1" && a.bind != "localhost")
        warn(SourceLocation{},
             "--bind " + a.bind + ": the viewer is reachable from other machines; anyone with the URL's token can drive it");
    ViewServer server(scene, a.input.scene, ViewServerOptions{a.bind == "localhost" ? "127.0.0.1" : a.bind, a.port});
    std::printf("candela view: serving %s at %s\n(Ctrl-C stops)\n", a.input.scene.c_str(), server.url().c_str());
    std::fflush(stdout);
    // Serves until a signal ends the process (core/stop.h: at once, with 130 or 143).
    for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
}

}  // namespace

void add_view_command(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<ViewArgs>();
    CLI::App* cmd = app.add_subcommand("view", "Show a scene live in a browser: path tracer and raster mode side by side");
    a->input.add_to(cmd);
    cmd->add_option("--port", a->port, "Port to serve on (default 0: a free port, printed with the URL)")
        ->check(whole_number("--port", "", 0, 65535));
    cmd->add_option("--bind", a->bind, "Address to listen on (default 127.0.0.1: this machine only; use an SSH tunnel to reach it)");
    cmd->callback([a, &run] { run = [a] { return view(*a); }; });
}

}  // namespace candela::app
