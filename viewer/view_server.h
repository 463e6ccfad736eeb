#pragma once
// The web server of `candela view` (and the Python API's candela.view): civetweb, Debian's
// libcivetweb, which serves HTTP and WebSockets from one small C library. It serves only its own
// page (viewer/assets/, compiled in), the current accumulation as EXR (/save.exr), and the
// WebSocket (/ws) through which pages drive a ViewSession and receive its frames. Every request
// and the WebSocket must carry the random token of the URL it prints (403 otherwise); any other
// path is 404. Protocol and controls: docs/viewer.md.

#include "core/scene.h"

#include <memory>
#include <string>

namespace candela {

struct ViewServerOptions {
    std::string bind = "127.0.0.1";
    int port = 0;  // 0: a free port chosen by the system
};

class ViewServer {
public:
    // Starts serving at once; InputError when the address cannot be bound.
    ViewServer(Ref<Scene> scene, const std::string& scene_path, const ViewServerOptions& options);
    ~ViewServer();
    ViewServer(const ViewServer&) = delete;
    ViewServer& operator=(const ViewServer&) = delete;

    int port() const;
    const std::string& token() const;
    // http://ADDRESS:PORT/?token=TOKEN
    std::string url() const;
    // Pages connected now.
    int clients() const;
    void stop();

    struct State;

private:
    std::unique_ptr<State> state_;
};

}  // namespace candela
