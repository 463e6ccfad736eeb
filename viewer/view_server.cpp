#include "viewer/view_server.h"

#include "core/error.h"
#include "core/film.h"
#include "core/scene.h"
#include "viewer/view_assets.h"
#include "viewer/view_session.h"

#include <civetweb.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <random>
#include <set>
#include <vector>

namespace candela {

namespace {

// The token: 128 random bits as hex (Jupyter's scheme). Compared in constant time.
std::string random_token() {
    std::random_device device;
    std::string token;
    const char* hex = "0123456789abcdef";
    for (int i = 0; i < 32; ++i) token += hex[device() & 15u];
    return token;
}

bool same_token(const std::string& a, const std::string& b) {
    if (a.size() != b.size()) return false;
    unsigned diff = 0;
    for (size_t i = 0; i < a.size(); ++i) diff |= unsigned(uint8_t(a[i]) ^ uint8_t(b[i]));
    return diff == 0;
}

std::string query_value(const char* query, const char* name) {
    if (!query) return "";
    char value[256];
    const int n = mg_get_var(query, std::strlen(query), name, value, sizeof value);
    return n >= 0 ? std::string(value, size_t(n)) : std::string();
}

// The largest message a page may send: settings and cameras are a few hundred bytes.
constexpr size_t MaxMessageBytes = 64 * 1024;

}  // namespace

struct ViewServer::State {
    std::string token, bind, scene_path;
    int port = 0;
    Ref<Scene> scene;
    std::unique_ptr<ViewSession> session;
    mg_context* context = nullptr;
    mutable std::mutex clients_mutex;
    std::set<mg_connection*> clients;

    bool authorised(const mg_request_info* ri) const { return same_token(query_value(ri->query_string, "token"), token); }

    // Sends to every page (binary frames or JSON text), dropping pages whose connection failed.
    void broadcast(int opcode, const std::string& bytes, mg_connection* except = nullptr) {
        std::lock_guard<std::mutex> lock(clients_mutex);
        for (mg_connection* c : clients) {
            if (c == except) continue;
            mg_lock_connection(c);
            mg_websocket_write(c, opcode, bytes.data(), bytes.size());
            mg_unlock_connection(c);
        }
    }
    // A page's id for the session: its connection, as a number.
    static uint64_t page_id(mg_connection* c) { return uint64_t(reinterpret_cast<uintptr_t>(c)); }
    void reply_to_page(uint64_t page, const std::string& text) {
        std::lock_guard<std::mutex> lock(clients_mutex);
        for (mg_connection* c : clients)
            if (page_id(c) == page) {
                mg_lock_connection(c);
                mg_websocket_write(c, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
                mg_unlock_connection(c);
            }
    }
    void reply(mg_connection* c, const std::string& text) {
        std::lock_guard<std::mutex> lock(clients_mutex);
        if (!clients.count(c)) return;
        mg_lock_connection(c);
        mg_websocket_write(c, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
        mg_unlock_connection(c);
    }
};

namespace {

int send_bytes(mg_connection* c, int status, const char* mime, const std::string& bytes, const char* extra_headers = "") {
    mg_printf(
        c,
        "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\n%s"
        "Connection: close\r\n\r\n",
        status,
        status == 200   ? "OK"
        : status == 403 ? "Forbidden"
                        : "Not Found",
        mime, bytes.size(), extra_headers);
    mg_write(c, bytes.data(), bytes.size());
    return status;
}

int handle_request(mg_connection* c, void* data) {
    auto& s = *static_cast<ViewServer::State*>(data);
    const mg_request_info* ri = mg_get_request_info(c);
    if (!s.authorised(ri)) return send_bytes(c, 403, "text/plain", "403: this page needs the token of the URL candela view printed\n");
    const std::string path = ri->local_uri ? ri->local_uri : "";
    if (std::strcmp(ri->request_method, "GET") != 0 && std::strcmp(ri->request_method, "HEAD") != 0)
        return send_bytes(c, 404, "text/plain", "404\n");
    if (path == "/save.exr") {
        std::string side = query_value(ri->query_string, "side");
        if (side.empty()) side = "left";
        try {
            auto bytes = s.session->save_exr(side);
            if (!bytes) return send_bytes(c, 404, "text/plain", "404: that side has no image yet\n");
            return send_bytes(c, 200, "image/x-exr", *bytes, "Content-Disposition: attachment; filename=candela-view.exr\r\n");
        } catch (const std::exception& e) {
            return send_bytes(c, 404, "text/plain", std::string("404: ") + e.what() + "\n");
        }
    }
    for (const ViewAsset& asset : view_assets())
        if (path == asset.path) return send_bytes(c, 200, asset.mime, std::string(asset.data, asset.size));
    return send_bytes(c, 404, "text/plain", "404\n");
}

int websocket_connect(const mg_connection* c, void* data) {
    auto& s = *static_cast<ViewServer::State*>(data);
    if (s.authorised(mg_get_request_info(c))) return 0;
    // Refused before the handshake, with the same 403 as a page without the token.
    // (civetweb's mg_send_http_error sends no status line at this stage: the response is written
    // whole here.)
    static const char body[] = "403: this connection needs the token of the URL candela view printed\n";
    mg_printf(const_cast<mg_connection*>(c),
              "HTTP/1.1 403 Forbidden\r\nContent-Type: text/plain\r\nContent-Length: %zu\r\nConnection: close\r\n\r\n%s", sizeof body - 1,
              body);
    return 1;
}

void websocket_ready(mg_connection* c, void* data) {
    auto& s = *static_cast<ViewServer::State*>(data);
    std::lock_guard<std::mutex> lock(s.clients_mutex);
    s.clients.insert(c);
    s.session->set_viewers(int(s.clients.size()));
}

int websocket_data(mg_connection* c, int bits, char* bytes, size_t length, void* data) {
    auto& s = *static_cast<ViewServer::State*>(data);
    const int opcode = bits & 0xf;
    if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
    if (opcode == MG_WEBSOCKET_OPCODE_PING || opcode == MG_WEBSOCKET_OPCODE_PONG) return 1;
    if (opcode != MG_WEBSOCKET_OPCODE_TEXT) {
        s.reply(c, R"({"type":"error","message":"messages are JSON text"})");
        return 1;
    }
    if (length > MaxMessageBytes) {
        s.reply(c, R"({"type":"error","message":"message too long"})");
        return 1;
    }
    std::string broadcast;
    const std::string answer = s.session->apply_message(ViewServer::State::page_id(c), std::string(bytes, length), broadcast);
    if (!answer.empty()) s.reply(c, answer);
    if (!broadcast.empty()) s.broadcast(MG_WEBSOCKET_OPCODE_TEXT, broadcast, c);
    return 1;
}

void websocket_close(const mg_connection* c, void* data) {
    auto& s = *static_cast<ViewServer::State*>(data);
    std::lock_guard<std::mutex> lock(s.clients_mutex);
    s.clients.erase(const_cast<mg_connection*>(c));
    s.session->set_viewers(int(s.clients.size()));
}

}  // namespace

ViewServer::ViewServer(Ref<Scene> scene, const std::string& scene_path, const ViewServerOptions& options)
    : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.token = random_token();
    s.bind = options.bind;
    s.scene_path = scene_path;
    s.scene = std::move(scene);
    require_colour_film(s.scene->sensor().film(), "the viewer shows colour images (its displays and its raster side)");
    if (options.port < 0 || options.port > 65535) throw InputError("--port must lie between 0 and 65535");
    for (char ch : options.bind)
        if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == ':' || ch == '[' || ch == ']'))
            throw InputError("--bind takes an IP address, got \"" + options.bind + "\"");
    ViewSink sink;
    sink.frame = [&s](const std::string& bytes) { s.broadcast(MG_WEBSOCKET_OPCODE_BINARY, bytes); };
    sink.text = [&s](const std::string& text) { s.broadcast(MG_WEBSOCKET_OPCODE_TEXT, text); };
    sink.reply = [&s](uint64_t page, const std::string& text) { s.reply_to_page(page, text); };
    s.session = std::make_unique<ViewSession>(s.scene, scene_path, sink);

    static std::once_flag library;
    std::call_once(library, [] { mg_init_library(MG_FEATURES_WEBSOCKET); });
    const std::string ports =
        (options.bind.find(':') != std::string::npos ? "[" + options.bind + "]" : options.bind) + ":" + std::to_string(options.port);
    // decode_url no: paths are compared as they were sent, so that no encoding (%2e%2e, %00)
    // reaches anything but a 404.
    const char* mg_options[] = {"listening_ports", ports.c_str(), "num_threads", "16", "enable_directory_listing", "no",
                                "decode_url",      "no",          nullptr};
    mg_callbacks callbacks;
    std::memset(&callbacks, 0, sizeof callbacks);
    callbacks.log_message = [](const mg_connection*, const char*) { return 1; };  // quiet
    s.context = mg_start(&callbacks, &s, mg_options);
    if (!s.context) {
        s.session->stop();
        throw InputError("cannot serve on " + ports + " (is the port in use, or the address not this machine's?)");
    }
    mg_set_request_handler(s.context, "/", handle_request, &s);
    mg_set_websocket_handler(s.context, "/ws", websocket_connect, websocket_ready, websocket_data, websocket_close, &s);
    mg_server_port server_ports[4];
    const int n = mg_get_server_ports(s.context, 4, server_ports);
    s.port = n > 0 ? server_ports[0].port : options.port;
}

ViewServer::~ViewServer() { stop(); }

void ViewServer::stop() {
    if (!state_) return;
    if (state_->session) state_->session->stop();
    if (state_->context) {
        mg_stop(state_->context);
        state_->context = nullptr;
    }
}

int ViewServer::port() const { return state_->port; }
const std::string& ViewServer::token() const { return state_->token; }
std::string ViewServer::url() const {
    const std::string host = state_->bind.find(':') != std::string::npos ? "[" + state_->bind + "]" : state_->bind;
    return "http://" + host + ":" + std::to_string(state_->port) + "/?token=" + state_->token;
}
int ViewServer::clients() const {
    std::lock_guard<std::mutex> lock(state_->clients_mutex);
    return int(state_->clients.size());
}

}  // namespace candela
